/// @file
/// @brief Solver mode, the whole pair (design note Sections 3.1 item 4 and 3.2; beyond the paper): the
/// candidates of both roles are reduced to at most 4 clusters of 4 points (reduceContacts), and each cluster is
/// written into one btPersistentManifold the way btManifoldResult::addContactPoint would, except for matching.
///
/// @details
/// - Bullet's sign: the normal is on body 1 (B) and points from B to A; distance > 0 when separated. A shell point
///   of A gives positionWorldOnA = p, positionWorldOnB = p - n d; a shell point of B gives positionWorldOnB = p,
///   positionWorldOnA = p + n d. Local points are in the collision objects' frames (as addContactPoint).
/// - Materials through Bullet's global combine callbacks (friction, restitution, rolling, spinning; contact stiffness
///   and damping and the friction anchor flag as addContactPoint sets them), so user overrides hold.
/// - Matching by identity, (role, shell point) kept in m_partId0/1 and m_index0/1, not by a radius: a matched point is
///   written with replaceContactPoint (keeps m_appliedImpulse, the lateral impulses and the lifetime: warm starting),
///   a new point takes a stale point's slot (cleared) or is added, and stale points left over are removed. A manifold
///   therefore empties only when its cluster is gone: gContactStartedCallback fires on 0 -> n points, Bullet's
///   removeContactPoint/clearManifold fire gContactEndedCallback on n -> 0. gContactAddedCallback runs for written
///   points when an object has CF_CUSTOM_MATERIAL_CALLBACK.
/// - Clusters go to the manifold holding most of their points, else to one whose normal is within 25 degrees, else to
///   an empty or new one (btDispatcher::getNewManifold); extra manifolds no cluster uses are released.
/// - The breaking threshold is raised to cover our speculative distances (refreshContactPoints, which compound shapes
///   call, would drop them); the processing threshold is Bullet's, so the solver answers every point.
#include "solver/solver_manifolds.h"

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "common/bullet_conversions.h"

namespace sdfccd::bullet::detail {
namespace {

constexpr double kClusterMatchCosine = 0.90630778703665;  // cos 25 deg, as reduceContacts' clusters

/// The candidate id (2 * shell point + role) a manifold point was written with.
int candidateId(const btManifoldPoint& pt) {
  const int role = pt.m_partId0;
  return 2 * (role == 0 ? pt.m_index0 : pt.m_index1) + role;
}

struct Material {
  btScalar friction = 0, restitution = 0, rolling = 0, spinning = 0, stiffness = 0, damping = 0;
  int flags = 0;
};

Material combinedMaterial(const btCollisionObject* a, const btCollisionObject* b) {
  Material m;
  m.friction = gCalculateCombinedFrictionCallback(a, b);
  m.restitution = gCalculateCombinedRestitutionCallback(a, b);
  m.rolling = gCalculateCombinedRollingFrictionCallback(a, b);
  m.spinning = gCalculateCombinedSpinningFrictionCallback(a, b);
  const int flags = a->getCollisionFlags() | b->getCollisionFlags();
  if (flags & btCollisionObject::CF_HAS_CONTACT_STIFFNESS_DAMPING) {
    m.stiffness = gCalculateCombinedContactStiffnessCallback(a, b);
    m.damping = gCalculateCombinedContactDampingCallback(a, b);
    m.flags |= BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING;
  }
  if (flags & btCollisionObject::CF_HAS_FRICTION_ANCHOR) m.flags |= BT_CONTACT_FLAG_FRICTION_ANCHOR;
  return m;
}

btManifoldPoint makePoint(const ContactCandidate& c, double distance, const btCollisionObject* a,
                          const btCollisionObject* b, const Material& m) {
  const int role = c.point & 1;
  const int shellPoint = c.point >> 1;
  const Vec3 onA = role == 0 ? c.position : Vec3(c.position + c.normal * distance);
  const Vec3 onB = role == 0 ? Vec3(c.position - c.normal * distance) : c.position;
  const btVector3 worldOnA = toBt(onA);
  const btVector3 worldOnB = toBt(onB);
  btManifoldPoint pt(a->getWorldTransform().invXform(worldOnA), b->getWorldTransform().invXform(worldOnB),
                     toBt(c.normal), btScalar(distance));
  pt.m_positionWorldOnA = worldOnA;
  pt.m_positionWorldOnB = worldOnB;
  pt.m_partId0 = pt.m_partId1 = role;
  pt.m_index0 = role == 0 ? shellPoint : -1;
  pt.m_index1 = role == 1 ? shellPoint : -1;
  pt.m_combinedFriction = m.friction;
  pt.m_combinedRestitution = m.restitution;
  pt.m_combinedRollingFriction = m.rolling;
  pt.m_combinedSpinningFriction = m.spinning;
  pt.m_contactPointFlags = m.flags;
  if (m.flags & BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING) {
    pt.m_combinedContactStiffness1 = m.stiffness;
    pt.m_combinedContactDamping1 = m.damping;
  }
  return pt;
}

/// Writes one cluster into `manifold` (see the file comment for the matching rules).
void writeCluster(btPersistentManifold* manifold, const ContactCluster& cluster,
                  const std::vector<ContactCandidate>& candidates, const std::vector<double>& distances,
                  const std::vector<double>& bounce, const btCollisionObjectWrapper* wrapA,
                  const btCollisionObjectWrapper* wrapB, const Material& material) {
  const btCollisionObject* a = wrapA->getCollisionObject();
  const btCollisionObject* b = wrapB->getCollisionObject();
  const bool wasEmpty = manifold->getNumContacts() == 0;
  std::array<int, kMaxPointsPerCluster> existingOf;
  existingOf.fill(-1);
  std::array<bool, MANIFOLD_CACHE_SIZE> kept{};
  for (int i = 0; i < manifold->getNumContacts(); ++i) {
    const int id = candidateId(manifold->getContactPoint(i));
    for (int j = 0; j < cluster.selectedCount; ++j) {
      if (candidates[static_cast<std::size_t>(cluster.selected[static_cast<std::size_t>(j)])].point == id) {
        existingOf[static_cast<std::size_t>(j)] = i;
        kept[static_cast<std::size_t>(i)] = true;
      }
    }
  }
  const bool callAdded = gContactAddedCallback != nullptr && ((a->getCollisionFlags() | b->getCollisionFlags()) &
                                                              btCollisionObject::CF_CUSTOM_MATERIAL_CALLBACK) != 0;
  for (int j = 0; j < cluster.selectedCount; ++j) {
    const std::size_t k = static_cast<std::size_t>(cluster.selected[static_cast<std::size_t>(j)]);
    // One normal per manifold, the cluster's mean (as Bullet's own manifolds have): single points' normals tilt
    // where a field's grid interpolation rounds an edge, and tilted rows push a resting stack sideways.
    ContactCandidate candidate = candidates[k];
    candidate.normal = cluster.normal;
    btManifoldPoint pt = makePoint(candidate, distances[k], a, b, material);
    // A point that hits during the step: the restitution that makes its rebound rise as from the contact
    // (solver_role.cpp, reboundCoefficient).
    if (pt.m_combinedRestitution > 0) pt.m_combinedRestitution += btScalar(bounce[k]);
    int index = existingOf[static_cast<std::size_t>(j)];
    if (index >= 0) {
      manifold->replaceContactPoint(pt, index);
      ++manifold->getContactPoint(index).m_lifeTime;
    } else {
      for (int i = 0; i < manifold->getNumContacts() && index < 0; ++i) {
        if (!kept[static_cast<std::size_t>(i)]) index = i;  // a stale point's slot: a new point, no history
      }
      if (index >= 0) {
        manifold->clearUserCache(manifold->getContactPoint(index));
        manifold->getContactPoint(index) = pt;
        kept[static_cast<std::size_t>(index)] = true;
      } else {
        index = manifold->addManifoldPoint(pt);
        kept[static_cast<std::size_t>(index)] = true;
      }
    }
    if (callAdded) {
      gContactAddedCallback(manifold->getContactPoint(index), wrapA, pt.m_partId0, pt.m_index0, wrapB, pt.m_partId1,
                            pt.m_index1);
    }
  }
  for (int i = manifold->getNumContacts() - 1; i >= 0; --i) {
    if (!kept[static_cast<std::size_t>(i)]) manifold->removeContactPoint(i);
  }
  if (wasEmpty && manifold->getNumContacts() > 0 && gContactStartedCallback != nullptr) {
    gContactStartedCallback(manifold);
  }
}

/// The angular velocity of `a` relative to `b` (rad/s, world); a collision object without a rigid body is still.
Vec3 relativeSpin(const btCollisionObject* a, const btCollisionObject* b) {
  const btRigidBody* ra = btRigidBody::upcast(a);
  const btRigidBody* rb = btRigidBody::upcast(b);
  const Vec3 wa = ra != nullptr ? toVec3(ra->getAngularVelocity()) : Vec3::Zero();
  const Vec3 wb = rb != nullptr ? toVec3(rb->getAngularVelocity()) : Vec3::Zero();
  return wa - wb;
}

/// A face's contact written as two point sets, so that its friction twists as a pressed patch does.
/// The reduction keeps a patch's outermost points (its corners) so that the normal rows hold the body up to the
/// patch's edge; friction rows at those corners resist a spin with the corners' lever arm (0.707 a on an a x a
/// face) instead of the patch's mean one (0.383 a: Coulomb friction over a uniformly pressed square), about
/// twice the twisting friction. So a patch whose corners lie well beyond its mean radius becomes
/// - the corners, a hair (kSupportSlack of their radius) farther than their gap: they carry load only once the
///   body tips toward them (a box on a steep incline, a rocking block), and hold it up to the patch's edge;
/// - the same points drawn in toward the patch's centroid to its mean radius (ContactCluster::spread): they carry
///   the resting load, and with it the friction (a point's friction is limited by mu times its own load), and
///   twist with the patch's lever arm.
/// The drawn-in points are new manifold points (their ids have kTwistIdBit set), in a manifold of their own. The
/// split is made while the patch twists (its mean radius slips faster than kTwistSlipSpeed about its normal); a
/// patch at rest keeps its corners alone, whose static friction then holds a twisting torque up to the corners'
/// lever arm.
struct SplitContacts {
  static constexpr double kSupportSlack = 1e-3;    // of the corners' mean radius
  static constexpr double kWorthSplitting = 0.9;   // split when spread < this share of the corners' radius
  static constexpr int kTwistIdBit = 1 << 29;      // shell point ids are below it (PointTree's bound: 2^30)
  static constexpr double kTwistSlipSpeed = 5e-3;  // m/s: the patch twists (its mean radius slips this fast)

  std::vector<ContactCandidate> points;
  std::vector<double> distance;
  std::vector<double> bounce;

  explicit SplitContacts(const SolverCandidates& c) : points(c.points), distance(c.distance), bounce(c.bounce) {}

  /// `spin`: the bodies' relative angular velocity (rad/s, world).
  void separateTwistingFriction(ReducedContacts& reduced, const Vec3& spin) {
    const int original = reduced.clusterCount;
    for (int k = 0; k < original && reduced.clusterCount < kMaxContactClusters; ++k) {
      ContactCluster& cluster = reduced.clusters[static_cast<std::size_t>(k)];
      if (cluster.selectedCount < 3 || cluster.memberCount <= cluster.selectedCount) continue;
      double cornerRadius = 0.0;
      for (int j = 0; j < cluster.selectedCount; ++j) {
        cornerRadius += inPlane(cluster, points[selectedAt(cluster, j)].position).norm();
      }
      cornerRadius /= cluster.selectedCount;
      if (!(cornerRadius > 0.0) || !(cluster.spread < kWorthSplitting * cornerRadius)) continue;
      if (!(std::abs(spin.dot(cluster.normal)) * cluster.spread > kTwistSlipSpeed)) continue;
      const double scale = cluster.spread / cornerRadius;
      ContactCluster& twist = reduced.clusters[static_cast<std::size_t>(reduced.clusterCount++)];
      twist = cluster;
      for (int j = 0; j < cluster.selectedCount; ++j) {
        const std::size_t corner = selectedAt(cluster, j);
        ContactCandidate drawnIn = points[corner];
        drawnIn.position -= (1.0 - scale) * inPlane(cluster, drawnIn.position);
        const int role = drawnIn.point & 1;
        drawnIn.point = 2 * ((drawnIn.point >> 1) | kTwistIdBit) + role;
        twist.selected[static_cast<std::size_t>(j)] = static_cast<int>(points.size());
        points.push_back(drawnIn);
        distance.push_back(distance[corner]);
        bounce.push_back(bounce[corner]);
        distance[corner] += kSupportSlack * cornerRadius;
      }
    }
  }

 private:
  static std::size_t selectedAt(const ContactCluster& cluster, int j) {
    return static_cast<std::size_t>(cluster.selected[static_cast<std::size_t>(j)]);
  }
  /// The offset of `position` from the cluster's centroid, in the cluster's plane.
  static Vec3 inPlane(const ContactCluster& cluster, const Vec3& position) {
    const Vec3 offset = position - cluster.centroid;
    return offset - offset.dot(cluster.normal) * cluster.normal;
  }
};

void removeAllPoints(btPersistentManifold* manifold) {
  for (int i = manifold->getNumContacts() - 1; i >= 0; --i) manifold->removeContactPoint(i);
}

}  // namespace

SolverPair* createSolverPair(btDispatcher* dispatcher, const btPersistentManifold* primary) {
  auto* pair = new SolverPair;
  pair->dispatcher = dispatcher;
  pair->bulletBreakingThreshold = double(primary->getContactBreakingThreshold());
  return pair;
}

void destroySolverPair(SolverPair* pair, btDispatcher* dispatcher) {
  if (pair == nullptr) return;
  for (btPersistentManifold* m : pair->extra) {
    if (m != nullptr) dispatcher->releaseManifold(m);  // clearManifold: gContactEndedCallback if it had points
  }
  delete pair;
}

void solverPairManifolds(const SolverPair* pair, btManifoldArray& manifoldArray) {
  if (pair == nullptr) return;
  for (btPersistentManifold* m : pair->extra) {
    if (m != nullptr) manifoldArray.push_back(m);
  }
}

void writeSolverManifolds(const btCollisionObjectWrapper* wrapA, const btCollisionObjectWrapper* wrapB,
                          btPersistentManifold* primary, SolverPair& pair, const SolverCandidates& candidates,
                          const SolverFriction& friction) {
  ReducedContacts reduced = reduceContacts(candidates.points, ContactReductionSettings{}, pair.previous);
  pair.previous = reduced.selectedPoints(candidates.points);
  SplitContacts split(candidates);
  split.separateTwistingFriction(reduced, relativeSpin(wrapA->getCollisionObject(), wrapB->getCollisionObject()));
  const std::vector<ContactCandidate>& points = split.points;
  const btCollisionObject* a = wrapA->getCollisionObject();
  const btCollisionObject* b = wrapB->getCollisionObject();

  std::array<btPersistentManifold*, kMaxContactClusters> slots{primary, pair.extra[0], pair.extra[1], pair.extra[2]};
  std::array<int, kMaxContactClusters> slotOf;
  slotOf.fill(-1);
  std::array<bool, kMaxContactClusters> slotUsed{};
  // 1. Each cluster to the manifold that holds most of its points (greedy, most shared points first).
  for (;;) {
    int best = 0, bestCluster = -1, bestSlot = -1;
    for (int c = 0; c < reduced.clusterCount; ++c) {
      if (slotOf[static_cast<std::size_t>(c)] >= 0) continue;
      const ContactCluster& cluster = reduced.clusters[static_cast<std::size_t>(c)];
      for (int s = 0; s < kMaxContactClusters; ++s) {
        btPersistentManifold* m = slots[static_cast<std::size_t>(s)];
        if (slotUsed[static_cast<std::size_t>(s)] || m == nullptr) continue;
        int shared = 0;
        for (int i = 0; i < m->getNumContacts(); ++i) {
          const int id = candidateId(m->getContactPoint(i));
          for (int j = 0; j < cluster.selectedCount; ++j) {
            shared += points[static_cast<std::size_t>(cluster.selected[static_cast<std::size_t>(j)])].point == id;
          }
        }
        if (shared > best) best = shared, bestCluster = c, bestSlot = s;
      }
    }
    if (bestCluster < 0) break;
    slotOf[static_cast<std::size_t>(bestCluster)] = bestSlot;
    slotUsed[static_cast<std::size_t>(bestSlot)] = true;
  }
  // 2. The others: a manifold with points along the cluster's normal (a rolling contact changes all its points),
  //    else an empty one, else a new one.
  for (int c = 0; c < reduced.clusterCount; ++c) {
    if (slotOf[static_cast<std::size_t>(c)] >= 0) continue;
    const Vec3& normal = reduced.clusters[static_cast<std::size_t>(c)].normal;
    int chosen = -1;
    double bestCosine = kClusterMatchCosine;
    for (int s = 0; s < kMaxContactClusters; ++s) {
      btPersistentManifold* m = slots[static_cast<std::size_t>(s)];
      if (slotUsed[static_cast<std::size_t>(s)] || m == nullptr || m->getNumContacts() == 0) continue;
      const double cosine = double(m->getContactPoint(0).m_normalWorldOnB.dot(toBt(normal)));
      if (cosine >= bestCosine) bestCosine = cosine, chosen = s;
    }
    for (int s = 0; s < kMaxContactClusters && chosen < 0; ++s) {
      btPersistentManifold* m = slots[static_cast<std::size_t>(s)];
      if (!slotUsed[static_cast<std::size_t>(s)] && (m == nullptr || m->getNumContacts() == 0)) chosen = s;
    }
    for (int s = 0; s < kMaxContactClusters && chosen < 0; ++s) {
      if (!slotUsed[static_cast<std::size_t>(s)]) chosen = s;
    }
    if (slots[static_cast<std::size_t>(chosen)] == nullptr) {
      slots[static_cast<std::size_t>(chosen)] = pair.dispatcher->getNewManifold(a, b);
    }
    slotOf[static_cast<std::size_t>(c)] = chosen;
    slotUsed[static_cast<std::size_t>(chosen)] = true;
  }

  // Thresholds: Bullet's processing threshold; a breaking threshold above every speculative distance.
  double largest = 0.0;
  for (double d : split.distance) largest = std::max(largest, d);
  const btScalar breaking = btScalar(std::max(pair.bulletBreakingThreshold, largest + 2.0 * candidates.margin));
  const btScalar processing = std::min(a->getContactProcessingThreshold(), b->getContactProcessingThreshold());
  Material material = combinedMaterial(a, b);
  // The world's friction settings hold in this mode too: without friction no friction rows (nor rolling or
  // spinning ones); a fixed coefficient replaces the bodies' combined one.
  if (!friction.enabled) {
    material.friction = material.rolling = material.spinning = 0;
  } else if (!friction.fromBodies) {
    material.friction = btScalar(friction.coefficient);
  }
  for (int c = 0; c < reduced.clusterCount; ++c) {
    btPersistentManifold* m = slots[static_cast<std::size_t>(slotOf[static_cast<std::size_t>(c)])];
    m->setContactBreakingThreshold(breaking);
    m->setContactProcessingThreshold(processing);
    writeCluster(m, reduced.clusters[static_cast<std::size_t>(c)], points, split.distance, split.bounce, wrapA, wrapB,
                 material);
  }
  // Manifolds without a cluster: emptied (the ended callback fires), the extra ones released.
  for (int s = 0; s < kMaxContactClusters; ++s) {
    btPersistentManifold* m = slots[static_cast<std::size_t>(s)];
    if (slotUsed[static_cast<std::size_t>(s)] || m == nullptr) continue;
    removeAllPoints(m);
    if (s > 0) {
      pair.dispatcher->releaseManifold(m);
      slots[static_cast<std::size_t>(s)] = nullptr;
    }
  }
  for (int s = 1; s < kMaxContactClusters; ++s)
    pair.extra[static_cast<std::size_t>(s - 1)] = slots[static_cast<std::size_t>(s)];
}

}  // namespace sdfccd::bullet::detail
