/// @file
/// @brief SdfccdContactSystem: CCD + continuous penalty per pair, clamping and impulses per step
/// (Section 4.1 and 5; see sdfccd_contact_system.h).
#include "sdfccd/bullet/sdfccd_contact_system.h"

#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btEmptyCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <LinearMath/btTransformUtil.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <sstream>
#include <type_traits>

#include "sdfccd/bullet/sdfccd_collision_algorithm.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/shell/analytic_shells.h"

namespace sdfccd {
namespace {

Vec3 toVec3(const btVector3& v) {
  return Vec3(v.x(), v.y(), v.z());
}
btVector3 toBt(const Vec3& v) {
  return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z()));
}

Rigid toRigid(const btTransform& t) {
  Rigid r = Rigid::Identity();
  const btQuaternion q = t.getRotation();
  r.linear() = Quat(q.w(), q.x(), q.y(), q.z()).normalized().toRotationMatrix();
  r.translation() = toVec3(t.getOrigin());
  return r;
}

btTransform toBt(const Rigid& r) {
  const Quat q(r.linear());
  return btTransform(btQuaternion(btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w())),
                     toBt(Vec3(r.translation())));
}

/// The pose at fraction t of the step: translation lerped, rotation slerped.
Rigid interpolatePose(const Rigid& start, const Rigid& end, double t) {
  Rigid r = Rigid::Identity();
  r.linear() = Quat(start.linear()).slerp(t, Quat(end.linear())).toRotationMatrix();
  r.translation() = start.translation() + t * (end.translation() - start.translation());
  return r;
}

/// Wall time (s), for the penalty integrals' statistics.
double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// CPU time of the calling thread (s): the CCD is single threaded, and on a shared machine wall time would
// count other processes.
double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

bool isPlane(const btCollisionShape* shape) {
  return shape->getShapeType() == STATIC_PLANE_PROXYTYPE;
}

/// The Bullet convex shapes our algorithm pairs with ours (each is an analytic field and a point shell).
bool isSupportedConvexType(int shapeType) {
  return shapeType == BOX_SHAPE_PROXYTYPE || shapeType == SPHERE_SHAPE_PROXYTYPE ||
         shapeType == CAPSULE_SHAPE_PROXYTYPE;
}
bool isSupportedConvex(const btCollisionShape* shape) {
  return isSupportedConvexType(shape->getShapeType());
}

/// The analytic field of a supported convex shape, centred at its body origin; calls `use(field)`. The
/// sizes include Bullet's collision margin (btBoxShape's half extents with margin are the box the user asked
/// for; a sphere's and a capsule's margin is their radius) and the local scaling.
template <class Use>
void withConvexField(const btCollisionShape* shape, Use use) {
  switch (shape->getShapeType()) {
    case BOX_SHAPE_PROXYTYPE:
      use(BoxField(toVec3(static_cast<const btBoxShape*>(shape)->getHalfExtentsWithMargin())));
      break;
    case SPHERE_SHAPE_PROXYTYPE:
      use(SphereField(Vec3::Zero(), double(static_cast<const btSphereShape*>(shape)->getRadius())));
      break;
    case CAPSULE_SHAPE_PROXYTYPE: {
      const auto* capsule = static_cast<const btCapsuleShape*>(shape);
      use(CapsuleField(double(capsule->getRadius()), double(capsule->getHalfHeight()), capsule->getUpAxis()));
      break;
    }
    default:
      throw Error("sdfccd contact: not a supported convex shape");
  }
}

}  // namespace

/// The motion of one collision object over the current step.
struct SdfccdContactSystem::BodyStep {
  const btCollisionObject* object = nullptr;
  btRigidBody* body = nullptr;  // null unless a dynamic rigid body
  Rigid worldFromBodyStart = Rigid::Identity();
  Rigid worldFromBodyEnd = Rigid::Identity();
  BodyVelocities velocity;  // of the centre of mass, which is the body origin
  double clampFraction = 1.0;
  bool clamped = false;

  bool finite() const {
    return worldFromBodyStart.matrix().allFinite() && worldFromBodyEnd.matrix().allFinite() && velocity.allFinite();
  }
};

/// One role of one pair over the current step.
struct SdfccdContactSystem::Record {
  std::size_t shell = 0;  // indices into m_bodies
  std::size_t field = 0;
  PenaltyResult penalty;
  double maxPenetrationCells = 0.0;
  double firstFraction = 1.0;
  bool clamp = false;
  bool applied = false;  // SameStep: the penalty impulses are already in the velocities
  double clampFraction = 1.0;
  struct ClampPoint {
    Vec3 pointInShell = Vec3::Zero();
    Vec3 normal = Vec3::Zero();  // world, out of the field body at the point's first contact
    Vec3 point = Vec3::Zero();   // world, where the point is at the clamp fraction
  };
  std::vector<ClampPoint> clampPoints;  // the deep-entering points, earliest first (at most kMaxClampPoints)
};

namespace {
constexpr std::size_t kMaxClampPoints = 32;   // inelastic impact points per record
constexpr int kImpactIterations = 8;          // sequential-impulse sweeps over them
constexpr double kConvexPointsAcross = 16.0;  // convex shapes: at least this many points across their thinnest size
}  // namespace

/// Who is the shell and who the field in one role.
struct SdfccdContactSystem::Role {
  std::size_t shell = 0;
  std::size_t field = 0;
  const PointTree* shellTree = nullptr;  // our model's tree, or a convex shape's surface points
  Rigid bodyFromField = Rigid::Identity();
  bool shellIsBody0 = true;
};

SdfccdContactSystem::SdfccdContactSystem(const SdfccdContactSettings& settings) {
  setSettings(settings);
}

SdfccdContactSystem::~SdfccdContactSystem() = default;

void SdfccdContactSystem::setSettings(const SdfccdContactSettings& settings) {
  const PenaltySettings& p = settings.penalty;
  if (!(p.friction >= 0.0) || !std::isfinite(p.friction) || !(p.frictionSlipSpeed > 0.0)) {
    throw Error("contact settings: friction must be finite and >= 0, frictionSlipSpeed > 0");
  }
  if (!(p.stiffness >= 0.0) || !std::isfinite(p.stiffness) || !(p.damping >= 0.0) || !std::isfinite(p.damping) ||
      p.subintervals < 1) {
    throw Error("contact settings: stiffness and damping must be finite and >= 0, subintervals >= 1");
  }
  if (!(settings.toiDepthCells >= 0.0) || !std::isfinite(settings.toiDepthCells)) {
    throw Error("contact settings: toiDepthCells must be finite and >= 0");
  }
  if (!(settings.convexPointSpacingCells > 0.0) || !std::isfinite(settings.convexPointSpacingCells) ||
      settings.convexMaxPoints < 12) {
    throw Error("contact settings: convexPointSpacingCells must be positive and finite, convexMaxPoints >= 12");
  }
  if (settings.maxManifoldPoints < 0 || settings.maxManifoldPoints > 4) {
    throw Error("contact settings: maxManifoldPoints must be in 0..4");
  }
  m_settings = settings;
}

void SdfccdContactSystem::registerWith(btCollisionDispatcher& dispatcher) {
  m_createFuncs.clear();
  m_createFuncs.push_back(std::make_unique<SdfccdCollisionAlgorithm::CreateFunc>(this, false));
  m_createFuncs.push_back(std::make_unique<SdfccdCollisionAlgorithm::CreateFunc>(this, true));
  m_createFuncs.push_back(std::make_unique<btEmptyAlgorithm::CreateFunc>());
  btCollisionAlgorithmCreateFunc* contacts = m_createFuncs[0].get();
  btCollisionAlgorithmCreateFunc* closest = m_createFuncs[1].get();
  btCollisionAlgorithmCreateFunc* empty = m_createFuncs[2].get();
  const int ours = CUSTOM_CONCAVE_SHAPE_TYPE;
  for (int other = 0; other < MAX_BROADPHASE_COLLISION_TYPES; ++other) {
    const bool supported = other == ours || other == STATIC_PLANE_PROXYTYPE || isSupportedConvexType(other);
    dispatcher.registerCollisionCreateFunc(ours, other, supported ? contacts : empty);
    dispatcher.registerCollisionCreateFunc(other, ours, supported ? contacts : empty);
    dispatcher.registerClosestPointsCreateFunc(ours, other, supported ? closest : empty);
    dispatcher.registerClosestPointsCreateFunc(other, ours, supported ? closest : empty);
  }
}

SdfccdContactSystem::BodyStep& SdfccdContactSystem::bodyStep(const btCollisionObjectWrapper* wrap, double timeStep) {
  const btCollisionObject* object = wrap->getCollisionObject();
  const auto found = m_bodyIndex.find(object);
  if (found != m_bodyIndex.end()) return m_bodies[found->second];
  BodyStep step;
  step.object = object;
  const btTransform start = wrap->getWorldTransform();
  btTransform end = start;
  const btRigidBody* rigid = btRigidBody::upcast(object);
  if (rigid != nullptr && !rigid->isStaticOrKinematicObject()) {
    step.body = const_cast<btRigidBody*>(rigid);  // impulses are applied later, in updateAction
    // The symplectic Euler step Bullet's integrateVelocities + integrateTransforms will take (no contact
    // constraints come from us): v' = v + F/m dt, w' = w + I^-1 tau dt, then the pose from (v', w').
    const btVector3 v0 = rigid->getLinearVelocity();
    const btVector3 w0 = rigid->getAngularVelocity();
    btVector3 v1 = v0;
    btVector3 w1 = w0;
    if (rigid->isActive()) {
      v1 += rigid->getTotalForce() * (rigid->getInvMass() * btScalar(timeStep));
      w1 += rigid->getInvInertiaTensorWorld() * rigid->getTotalTorque() * btScalar(timeStep);
    }
    btTransformUtil::integrateTransform(start, v1, w1, btScalar(timeStep), end);
    step.velocity.linearStart = toVec3(v0);
    step.velocity.linearEnd = toVec3(v1);
    step.velocity.angularStart = toVec3(w0);
    step.velocity.angularEnd = toVec3(w1);
  } else if (rigid != nullptr && rigid->isKinematicObject()) {
    const btVector3 v = rigid->getLinearVelocity();
    const btVector3 w = rigid->getAngularVelocity();
    btTransformUtil::integrateTransform(start, v, w, btScalar(timeStep), end);
    step.velocity.linearStart = step.velocity.linearEnd = toVec3(v);
    step.velocity.angularStart = step.velocity.angularEnd = toVec3(w);
  }
  step.worldFromBodyStart = toRigid(start);
  step.worldFromBodyEnd = toRigid(end);
  m_bodyIndex.emplace(object, m_bodies.size());
  m_bodies.push_back(step);
  return m_bodies.back();
}

void SdfccdContactSystem::processPair(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                                      const btDispatcherInfo& dispatchInfo, btManifoldResult* resultOut,
                                      btPersistentManifold* manifold, bool closestPointsOnly) {
  const btCollisionShape* shape0 = wrap0->getCollisionShape();
  const btCollisionShape* shape1 = wrap1->getCollisionShape();
  const bool ours0 = isSdfccdShape(shape0);
  const bool ours1 = isSdfccdShape(shape1);
  manifold->clearManifold();
  resultOut->setPersistentManifold(manifold);
  const bool other1 = isPlane(shape1) || isSupportedConvex(shape1);
  if (!(ours0 && (ours1 || other1)) && !(ours1 && (isPlane(shape0) || isSupportedConvex(shape0)))) {
    ++m_stats.unsupportedPairs;  // e.g. btSdfCollisionShape, which shares our type id
    return;
  }
  const double timeStep = dispatchInfo.m_timeStep > 0 ? double(dispatchInfo.m_timeStep) : 1.0 / 60.0;
  // Closest-point queries use fresh, local body states (poses now, nothing moves).
  std::vector<BodyStep> savedBodies;
  std::unordered_map<const btCollisionObject*, std::size_t> savedIndex;
  if (closestPointsOnly) {
    savedBodies.swap(m_bodies);
    savedIndex.swap(m_bodyIndex);
  }
  const std::size_t index0 = static_cast<std::size_t>(&bodyStep(wrap0, timeStep) - m_bodies.data());
  const std::size_t index1 = static_cast<std::size_t>(&bodyStep(wrap1, timeStep) - m_bodies.data());
  // A body with a non-finite state (set by the user; Bullet integrates whatever it is given) takes part in
  // no contact: its impulses would carry the NaN into the other body.
  if (!m_bodies[index0].finite() || !m_bodies[index1].finite()) {
    ++m_stats.nonFinitePairs;
    if (closestPointsOnly) {
      m_bodies.swap(savedBodies);
      m_bodyIndex.swap(savedIndex);
    }
    return;
  }

  // One role: the shell of `shellWrap` (ours, or a convex's surface points) against the field of `fieldWrap`
  // (ours, or a plane's or a convex's analytic field).
  auto runRole = [&](std::size_t shell, std::size_t field, const btCollisionObjectWrapper* shellWrap,
                     const btCollisionObjectWrapper* fieldWrap, bool shellIsBody0) {
    Role role;
    role.shell = shell;
    role.field = field;
    role.shellIsBody0 = shellIsBody0;
    const btCollisionShape* shellShape = shellWrap->getCollisionShape();
    const btCollisionShape* fieldShape = fieldWrap->getCollisionShape();
    if (isSdfccdShape(fieldShape)) {
      const SdfccdBodyModel& fieldModel = static_cast<const SdfccdShape*>(fieldShape)->model();
      role.bodyFromField = fieldModel.bodyFromField();
      role.shellTree = isSdfccdShape(shellShape) ? &static_cast<const SdfccdShape*>(shellShape)->model().tree()
                                                 : &convexShellTree(shellShape, fieldModel.cellSize());
      processRole(role, fieldModel.field(), m_settings.toiDepthCells, fieldModel.cellSize(), timeStep, resultOut,
                  closestPointsOnly);
      return;
    }
    // An analytic field: depths are reported in cells of the shell body's own field.
    const SdfccdBodyModel& shellModel = static_cast<const SdfccdShape*>(shellShape)->model();
    role.shellTree = &shellModel.tree();
    const double shellCell = shellModel.cellSize();
    if (isPlane(fieldShape)) {
      const auto* plane = static_cast<const btStaticPlaneShape*>(fieldShape);
      const PlaneField planeField(toVec3(plane->getPlaneNormal()), double(plane->getPlaneConstant()));
      processRole(role, planeField, m_settings.toiDepthCells, shellCell, timeStep, resultOut, closestPointsOnly);
    } else {
      withConvexField(fieldShape, [&](const auto& convexField) {
        processRole(role, convexField, m_settings.toiDepthCells, shellCell, timeStep, resultOut, closestPointsOnly);
      });
    }
  };
  // Every body with a shell takes the shell role once: ours always; a convex only against our field.
  if (ours0 || ours1)
    runRole(ours0 ? index0 : index1, ours0 ? index1 : index0, ours0 ? wrap0 : wrap1, ours0 ? wrap1 : wrap0, ours0);
  const btCollisionShape* second = ours0 ? shape1 : shape0;
  if (ours0 && ours1) {
    runRole(index1, index0, wrap1, wrap0, false);
  } else if (isSupportedConvex(second)) {
    runRole(ours0 ? index1 : index0, ours0 ? index0 : index1, ours0 ? wrap1 : wrap0, ours0 ? wrap0 : wrap1, !ours0);
  }

  if (closestPointsOnly) {
    m_bodies.swap(savedBodies);
    m_bodyIndex.swap(savedIndex);
  }
}

template <class Field>
void SdfccdContactSystem::processRole(const Role& role, const Field& field, double thresholdCells, double cellSize,
                                      double timeStep, btManifoldResult* resultOut, bool closestPointsOnly) {
  const BodyStep& shell = m_bodies[role.shell];
  const BodyStep& fieldBody = m_bodies[role.field];
  const PointTree& tree = *role.shellTree;
  const PointShell& shellPoints = tree.shell();
  const bool discrete = closestPointsOnly || m_settings.penalty.model == PenaltyModel::Discrete;

  // The frame contract of queryContacts (contact_query.h): the shell's points live in its body frame (whose
  // origin is the centre of mass); the field's frame sits at bodyFromField in its body. A closest-point query
  // looks at the current poses: nothing moves.
  ShellMotion shellMotion;
  shellMotion.worldFromShellStart = shell.worldFromBodyStart;
  shellMotion.worldFromShellEnd = closestPointsOnly ? shell.worldFromBodyStart : shell.worldFromBodyEnd;
  shellMotion.velocity = shell.velocity;
  FieldMotion fieldMotion;
  fieldMotion.worldFromSdfStart = fieldBody.worldFromBodyStart * role.bodyFromField;
  fieldMotion.worldFromSdfEnd =
      closestPointsOnly ? fieldMotion.worldFromSdfStart : Rigid(fieldBody.worldFromBodyEnd * role.bodyFromField);
  fieldMotion.centerOfMassInSdf = role.bodyFromField.inverse().translation();
  fieldMotion.velocity = fieldBody.velocity;
  const Rigid& worldFromShellEnd = shellMotion.worldFromShellEnd;
  const Rigid& worldFromFieldStart = fieldMotion.worldFromSdfStart;
  const Rigid& worldFromFieldEnd = fieldMotion.worldFromSdfEnd;

  ContactQuerySettings query;
  query.penalty = m_settings.penalty;
  if (discrete) query.penalty.model = PenaltyModel::Discrete;
  query.discreteMode = CcdMode::AllIntervals;  // every contact at the end pose
  query.octree = m_settings.octree;
  query.useTree = m_settings.useTree;
  query.threads = 1;
  query.integratePenalty = !closestPointsOnly;
  ContactQueryClocks clocks;
  clocks.ccd = &threadCpuSeconds;
  clocks.penalty = &steadySeconds;
  queryContacts(tree, field, shellMotion, fieldMotion, timeStep, query, m_scratch, clocks);
  const RigidCcdResult& ccdResult = m_scratch.ccd;
  const Rigid& sdfFromShellStart = m_scratch.sdfFromShellStart;
  const Rigid& sdfFromShellEnd = m_scratch.sdfFromShellEnd;
  if (!closestPointsOnly && m_settings.shadowLinearEvery > 0 && m_stepCounter % m_settings.shadowLinearEvery == 0 &&
      !std::is_same_v<Field, PlaneField>) {
    RigidCcdSettings linear;
    linear.sigma = query.penalty.sigma;
    linear.mode = discrete ? query.discreteMode : CcdMode::AllIntervals;
    linear.octree = query.octree;
    linear.useTree = false;
    linear.threads = 1;
    const double shadowStart = threadCpuSeconds();
    rigidCcd(tree, field, discrete ? sdfFromShellEnd : sdfFromShellStart, sdfFromShellEnd, linear, m_shadowScratch);
    m_stats.shadowLinearSeconds += threadCpuSeconds() - shadowStart;
  }
  m_stats.ccdSeconds += m_scratch.ccdSeconds;
  if constexpr (std::is_same_v<Field, PlaneField>) {
    m_stats.groundCcdSeconds += m_scratch.ccdSeconds;
    ++m_stats.groundCcdQueries;
  }
  ++m_stats.ccdQueries;
  m_stats.segmentQueries += ccdResult.stats.segmentQueries;
  if (ccdResult.contacts.empty()) return;

  // Manifold points: the deepest points at the step's end, for users (the solver ignores them).
  if (m_settings.maxManifoldPoints > 0) {
    std::vector<std::pair<double, int>> deepest;
    for (int i = 0; i < static_cast<int>(ccdResult.contacts.size()); ++i) {
      if (ccdResult.contacts[static_cast<std::size_t>(i)].depthAtEnd < 0.0) {
        deepest.emplace_back(ccdResult.contacts[static_cast<std::size_t>(i)].depthAtEnd, i);
      }
    }
    const std::size_t keep = std::min(deepest.size(), static_cast<std::size_t>(m_settings.maxManifoldPoints));
    std::partial_sort(deepest.begin(), deepest.begin() + static_cast<std::ptrdiff_t>(keep), deepest.end());
    for (std::size_t k = 0; k < keep; ++k) {
      const PointContact& c = ccdResult.contacts[static_cast<std::size_t>(deepest[k].second)];
      const Vec3& pointInShell = shellPoints.positions[static_cast<std::size_t>(c.point)];
      const Vec3 pointInWorld = worldFromShellEnd * pointInShell;
      Vec3 gradientInWorld = worldFromFieldEnd.linear() * field.gradient(sdfFromShellEnd * pointInShell);
      if (!(gradientInWorld.norm() > 0.0)) continue;
      gradientInWorld.normalize();
      const double depth = c.depthAtEnd;
      if (role.shellIsBody0) {
        // B is the field: its outward normal points towards A; the point on B is on the field's surface.
        resultOut->addContactPoint(toBt(gradientInWorld), toBt(Vec3(pointInWorld - gradientInWorld * depth)),
                                   btScalar(depth));
      } else {
        // B is the shell: its point is on B, and B's normal towards A is minus A's field gradient.
        resultOut->addContactPoint(toBt(Vec3(-gradientInWorld)), toBt(pointInWorld), btScalar(depth));
      }
    }
  }
  if (closestPointsOnly) return;

  Record record;
  record.shell = role.shell;
  record.field = role.field;
  record.penalty = m_scratch.penalty;
  m_stats.penaltySeconds += m_scratch.penaltySeconds;
  m_stats.penaltySamples += record.penalty.samples;
  m_stats.dampingEvaluations += record.penalty.dampingEvaluations;
  m_stats.torqueEvaluations += record.penalty.torqueEvaluations;
  m_stats.frictionEvaluations += record.penalty.frictionEvaluations;
  record.maxPenetrationCells = record.penalty.maxPenetration / cellSize;
  record.firstFraction = ccdResult.firstFraction;

  if (!discrete && m_settings.timeOfImpactClamp) {
    // A point that entered during the step and went deeper than the threshold (at an interval's middle, or
    // at the end) would be stopped too late by forces that act one step later: clamp at its first hit.
    const double threshold = thresholdCells * cellSize;
    std::vector<std::pair<double, Record::ClampPoint>> entering;
    for (const PointContact& c : ccdResult.contacts) {
      if (c.state != SegmentState::Hit || !(c.fraction > 0.0) || c.intervals.empty()) continue;
      const Vec3& pointInShell = shellPoints.positions[static_cast<std::size_t>(c.point)];
      const Vec3 p0 = sdfFromShellStart * pointInShell;
      const Vec3 p1 = sdfFromShellEnd * pointInShell;
      double deepest = c.depthAtEnd;
      for (std::size_t i = 0; i < c.intervals.size(); ++i) {
        const double t = 0.5 * (c.intervals[i].begin + c.intervals[i].end);
        deepest = std::min(deepest, field.distance(p0 + t * (p1 - p0)) - query.penalty.sigma);
      }
      if (!(deepest < -threshold)) continue;
      Record::ClampPoint clampPoint;
      clampPoint.pointInShell = pointInShell;
      clampPoint.normal = (worldFromFieldStart.linear() * c.fieldNormalInSdf).normalized();
      if (!clampPoint.normal.allFinite()) continue;
      entering.emplace_back(c.fraction, clampPoint);
    }
    if (!entering.empty()) {
      std::stable_sort(entering.begin(), entering.end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
      if (entering.size() > kMaxClampPoints) entering.resize(kMaxClampPoints);
      record.clamp = true;
      record.clampFraction = entering.front().first;
      for (auto& e : entering) {
        const Vec3 startInWorld = shell.worldFromBodyStart * e.second.pointInShell;
        e.second.point =
            startInWorld + record.clampFraction * (shell.worldFromBodyEnd * e.second.pointInShell - startInWorld);
        record.clampPoints.push_back(e.second);
      }
    }
    if (record.clamp) {
      // The bodies go back to the clamp fraction: report the penetration there, not along the discarded path.
      double deepest = 0.0;
      for (const PointContact& c : ccdResult.contacts) {
        const Vec3& pointInShell = shellPoints.positions[static_cast<std::size_t>(c.point)];
        const Vec3 p0 = sdfFromShellStart * pointInShell;
        const Vec3 p1 = sdfFromShellEnd * pointInShell;
        deepest = std::max(deepest, -(field.distance(p0 + record.clampFraction * (p1 - p0)) - query.penalty.sigma));
      }
      record.maxPenetrationCells = deepest / cellSize;
      record.penalty.maxPenetration = deepest;
    }
  }
  if (m_settings.forceTiming == SdfccdForceTiming::SameStep && !record.clamp) {
    applyPenaltyImpulses(record);
    record.applied = true;
  }
  m_records.push_back(record);
}

const PointTree& SdfccdContactSystem::convexShellTree(const btCollisionShape* shape, double fieldCellSize) {
  // Keyed by the shape's type and sizes (not its address, which a deleted shape may hand on) and the spacing.
  std::ostringstream key;
  key.precision(17);
  double smallestExtent = 0.0;  // the shape's thinnest size (m)
  withConvexField(shape, [&](const auto& field) {
    using Field = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<Field, BoxField>) {
      key << ' ' << field.halfExtents().transpose();
      smallestExtent = 2.0 * field.halfExtents().minCoeff();
    }
    if constexpr (std::is_same_v<Field, SphereField>) {
      key << ' ' << field.radius();
      smallestExtent = 2.0 * field.radius();
    }
    if constexpr (std::is_same_v<Field, CapsuleField>) {
      key << ' ' << field.radius() << ' ' << field.halfHeight() << ' ' << field.axis();
      smallestExtent = 2.0 * field.radius();
    }
  });
  // Fine enough for the field it meets, and for the shape itself: a small sphere on a coarse field still
  // rests on a patch of points, not on one.
  const double spacing =
      std::min(m_settings.convexPointSpacingCells * fieldCellSize, smallestExtent / kConvexPointsAcross);
  key << ' ' << shape->getShapeType() << ' ' << spacing;
  auto found = m_convexTrees.find(key.str());
  if (found != m_convexTrees.end()) return *found->second;
  AnalyticShellSettings sampling;
  sampling.spacing = spacing;
  sampling.maxPoints = m_settings.convexMaxPoints;
  PointShell points;
  withConvexField(shape, [&](const auto& field) {
    using Field = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<Field, BoxField>) points = boxShell(field.halfExtents(), sampling);
    if constexpr (std::is_same_v<Field, SphereField>) points = sphereShell(field.radius(), sampling);
    if constexpr (std::is_same_v<Field, CapsuleField>)
      points = capsuleShell(field.radius(), field.halfHeight(), field.axis(), sampling);
  });
  auto tree = std::make_unique<PointTree>(std::move(points));
  return *m_convexTrees.emplace(key.str(), std::move(tree)).first->second;
}

void SdfccdContactSystem::applyPenaltyImpulses(const Record& r) {
  for (int side = 0; side < 2; ++side) {
    btRigidBody* body = m_bodies[side == 0 ? r.shell : r.field].body;
    if (body == nullptr) continue;
    const Vec3& impulse = side == 0 ? r.penalty.impulseOnShell : r.penalty.impulseOnField;
    const Vec3& angular = side == 0 ? r.penalty.angularImpulseOnShell : r.penalty.angularImpulseOnField;
    if (impulse.isZero(0.0) && angular.isZero(0.0)) continue;
    if (!impulse.allFinite() || !angular.allFinite()) continue;  // never spread a NaN (see nonFinitePairs)
    body->applyCentralImpulse(toBt(impulse));
    if (!angular.isZero(0.0)) body->applyTorqueImpulse(toBt(angular));
    if (body->getActivationState() == ISLAND_SLEEPING) body->activate();
  }
}

void SdfccdContactSystem::updateAction(btCollisionWorld*, btScalar) {
  if (m_settings.shadowLinearEvery > 0 && m_stepCounter % m_settings.shadowLinearEvery == 0) ++m_stats.shadowSteps;
  ++m_stepCounter;
  m_lastContacts.clear();
  m_lastContactCount = 0;
  m_lastMaxPenetrationCells = 0.0;
  m_lastClamps = 0;

  // 1. Time-of-impact clamping: each dynamic body goes back to its earliest clamp fraction.
  for (const Record& r : m_records) {
    if (!r.clamp) continue;
    for (std::size_t side : {r.shell, r.field}) {
      BodyStep& b = m_bodies[side];
      if (b.body != nullptr) b.clampFraction = std::min(b.clampFraction, r.clampFraction);
    }
  }
  for (BodyStep& b : m_bodies) {
    if (b.body == nullptr || !(b.clampFraction < 1.0)) continue;
    b.clamped = true;
    b.body->setCenterOfMassTransform(toBt(interpolatePose(b.worldFromBodyStart, b.worldFromBodyEnd, b.clampFraction)));
    ++m_lastClamps;
    ++m_stats.clamps;
  }
  // 2. Inelastic impact: sequential impulses at the entering points remove their approaching normal
  //    velocity (accumulated impulse per point kept >= 0, so a later sweep may only take back what it gave).
  for (const Record& r : m_records) {
    if (!r.clamp) continue;
    btRigidBody* shell = m_bodies[r.shell].body;
    btRigidBody* fieldBody = m_bodies[r.field].body;
    // The points moved with the bodies to the clamp fraction; rebuild them from the shell's pose there.
    std::vector<btScalar> accumulated(r.clampPoints.size(), btScalar(0));
    for (int sweep = 0; sweep < kImpactIterations; ++sweep) {
      for (std::size_t k = 0; k < r.clampPoints.size(); ++k) {
        const btVector3 normal = toBt(r.clampPoints[k].normal);  // the shell may move along +normal
        const btVector3 point = toBt(r.clampPoints[k].point);
        btVector3 relativeVelocity(0, 0, 0);
        btScalar denominator = 0;
        btVector3 shellArm(0, 0, 0), fieldArm(0, 0, 0);
        if (shell != nullptr) {
          shellArm = point - shell->getCenterOfMassPosition();
          relativeVelocity += shell->getVelocityInLocalPoint(shellArm);
          denominator += shell->computeImpulseDenominator(point, normal);
        }
        if (fieldBody != nullptr) {
          fieldArm = point - fieldBody->getCenterOfMassPosition();
          relativeVelocity -= fieldBody->getVelocityInLocalPoint(fieldArm);
          denominator += fieldBody->computeImpulseDenominator(point, normal);
        }
        if (!(denominator > 0)) continue;
        const btScalar approach = relativeVelocity.dot(normal);
        const btScalar next = std::max(btScalar(0), accumulated[k] - approach / denominator);
        const btVector3 impulse = normal * (next - accumulated[k]);
        accumulated[k] = next;
        if (shell != nullptr) shell->applyImpulse(impulse, shellArm);
        if (fieldBody != nullptr) fieldBody->applyImpulse(-impulse, fieldArm);
      }
    }
    for (btRigidBody* body : {shell, fieldBody}) {
      if (body != nullptr && body->getActivationState() == ISLAND_SLEEPING) body->activate();
    }
  }
  // 3. NextStep timing: penalty impulses (eq. 5: F* dt) of the pairs whose bodies were not moved back.
  for (const Record& r : m_records) {
    const bool skip = r.applied || r.clamp || m_bodies[r.shell].clamped || m_bodies[r.field].clamped;
    if (!skip) applyPenaltyImpulses(r);
    SdfccdPairContact report;
    report.shellObject = m_bodies[r.shell].object;
    report.fieldObject = m_bodies[r.field].object;
    report.contactCount = r.penalty.contactCount;
    report.maxPenetration = r.penalty.maxPenetration;
    report.maxPenetrationCells = r.maxPenetrationCells;
    report.forceOnShell = r.penalty.forceOnShell;
    report.torqueOnShell = r.penalty.torqueOnShell;
    report.forceOnField = r.penalty.forceOnField;
    report.torqueOnField = r.penalty.torqueOnField;
    report.clamped = r.clamp;
    report.firstFraction = r.firstFraction;
    m_lastContacts.push_back(report);
    m_lastContactCount += r.penalty.contactCount;
    m_lastMaxPenetrationCells = std::max(m_lastMaxPenetrationCells, r.maxPenetrationCells);
  }
  m_stats.maxPenetrationCells = std::max(m_stats.maxPenetrationCells, m_lastMaxPenetrationCells);
  m_records.clear();
  m_bodies.clear();
  m_bodyIndex.clear();
}

std::shared_ptr<SdfccdContactSystem> registerSdfccdAlgorithms(btCollisionDispatcher* dispatcher,
                                                              const SdfccdContactSettings& settings) {
  if (dispatcher == nullptr) throw Error("registerSdfccdAlgorithms: the dispatcher is null");
  auto system = std::make_shared<SdfccdContactSystem>(settings);
  system->registerWith(*dispatcher);
  return system;
}

std::shared_ptr<SdfccdContactSystem> registerSdfccdAlgorithms(btDiscreteDynamicsWorld* world,
                                                              const SdfccdContactSettings& settings) {
  if (world == nullptr) throw Error("registerSdfccdAlgorithms: the world is null");
  auto* dispatcher = dynamic_cast<btCollisionDispatcher*>(world->getDispatcher());
  if (dispatcher == nullptr)
    throw Error("registerSdfccdAlgorithms: the world's dispatcher is not a btCollisionDispatcher");
  auto system = registerSdfccdAlgorithms(dispatcher, settings);
  world->addAction(system.get());
  return system;
}

}  // namespace sdfccd
