// The pose helpers of bullet_pose.h (at the end). rayTest and convexSweepTest against an SdfccdShape
// (sdfccd_shape_queries.cpp) give the triangle mesh's answers: rays against a brute-force scan of every triangle
// (Bullet's own per-triangle test), sweeps against a btBvhTriangleMeshShape of the same triangles. Hits, misses, rays
// starting inside, grazing rays, all-hits.
#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <btBulletCollisionCommon.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "bullet_test_util.h"
#include "sdfccd/bullet/bullet_pose.h"
#include "sdfccd/bullet/sdfccd_shape.h"

namespace sdfccd {
namespace queries_test {

std::shared_ptr<const BodyModel> bunnyModel() {
  static const std::shared_ptr<const BodyModel> model = test::buildTestBunny(200);
  return model;
}

/// Every triangle through Bullet's per-triangle ray test, in the body frame: the closest hit (or all hits).
struct BruteForceRay : btTriangleRaycastCallback {
  BruteForceRay(const btVector3& from, const btVector3& to) : btTriangleRaycastCallback(from, to) {}
  btScalar reportHit(const btVector3& normal, btScalar fraction, int, int triangleIndex) override {
    ++hits;
    if (fractions) fractions->push_back(fraction);
    if (fraction < closest) {
      closest = fraction;
      closestNormal = normal;
      closestTriangle = triangleIndex;
    }
    return m_hitFraction;  // keep every hit (all-hits); `closest` keeps the nearest
  }
  int hits = 0;
  btScalar closest = 1;
  btVector3 closestNormal;
  int closestTriangle = -1;
  std::vector<btScalar>* fractions = nullptr;  ///< every hit's fraction, when set
};

/// The body-frame triangles of the bunny as btVector3 triples (converted once).
const std::vector<btVector3>& bunnyCorners() {
  static const std::vector<btVector3> corners = [] {
    const TriangleMesh& mesh = bunnyModel()->meshInBody();
    std::vector<btVector3> out;
    for (const auto& t : mesh.triangles) {
      for (int k = 0; k < 3; ++k) out.push_back(bullet::toBtVector3(mesh.vertices[std::size_t(t[std::size_t(k)])]));
    }
    return out;
  }();
  return corners;
}

/// Scans every triangle of the bunny with `ray`.
void scanAll(BruteForceRay& ray) {
  std::vector<btVector3> corners = bunnyCorners();  // processTriangle takes non-const corners
  for (std::size_t t = 0; 3 * t < corners.size(); ++t) ray.processTriangle(&corners[3 * t], 0, static_cast<int>(t));
}

BruteForceRay bruteForce(const btVector3& fromLocal, const btVector3& toLocal) {
  BruteForceRay ray(fromLocal, toLocal);
  scanAll(ray);
  return ray;
}

/// A collision world holding the bunny at a tilted pose, as our shape and as a btBvhTriangleMeshShape.
class QueryWorld {
 public:
  QueryWorld() : model_(bunnyModel()), ours_(model_) {
    const TriangleMesh& mesh = model_->meshInBody();
    for (const auto& t : mesh.triangles) {
      triangles_.addTriangle(bullet::toBtVector3(mesh.vertices[std::size_t(t[0])]),
                             bullet::toBtVector3(mesh.vertices[std::size_t(t[1])]),
                             bullet::toBtVector3(mesh.vertices[std::size_t(t[2])]));
    }
    bvh_ = std::make_unique<btBvhTriangleMeshShape>(&triangles_, true);
    pose_ = btTransform(btQuaternion(btVector3(1, 2, 3).normalized(), 0.7f), btVector3(0.3f, -0.2f, 0.1f));
    oursObject_.setCollisionShape(&ours_);
    oursObject_.setWorldTransform(pose_);
    bvhObject_.setCollisionShape(bvh_.get());
    bvhObject_.setWorldTransform(pose_);
    oursWorld_.addCollisionObject(&oursObject_);
    bvhWorld_.addCollisionObject(&bvhObject_);
  }
  ~QueryWorld() {
    oursWorld_.removeCollisionObject(&oursObject_);
    bvhWorld_.removeCollisionObject(&bvhObject_);
  }
  const BodyModel& model() const { return *model_; }
  const btTransform& pose() const { return pose_; }
  double size() const { return model_->boundsInBody().diagonal().norm(); }
  btVector3 centreWorld() const { return pose_(bullet::toBtVector3(model_->boundsInBody().center())); }
  btCollisionWorld& ours() { return oursWorld_; }
  btCollisionWorld& bvh() { return bvhWorld_; }

  /// Our closest hit against the brute-force scan of the same ray in the body frame (Bullet's transform).
  void expectSameClosestHit(const btVector3& from, const btVector3& to, unsigned int flags = 0) {
    btCollisionWorld::ClosestRayResultCallback ray(from, to);
    ray.m_flags = flags;
    oursWorld_.rayTest(from, to, ray);
    const btTransform inverse = pose_.inverse();
    BruteForceRay reference(inverse * from, inverse * to);
    reference.m_flags = flags;
    scanAll(reference);
    ASSERT_EQ(ray.hasHit(), reference.hits > 0);
    if (!ray.hasHit()) return;
    EXPECT_NEAR(ray.m_closestHitFraction, reference.closest, 1e-6);
    const btVector3 expectedPoint = from.lerp(to, reference.closest);
    EXPECT_LT((ray.m_hitPointWorld - expectedPoint).length(), 1e-5 * size());
    // The triangle's normal, in world, flipped towards the ray's start (Bullet's convention).
    const btVector3 expectedNormal = pose_.getBasis() * reference.closestNormal;
    if (ray.m_hitNormalWorld.dot(expectedNormal) < 0.999f) {
      // Only a hit on a shared edge or vertex may name the other triangle, at the same fraction.
      EXPECT_NEAR(ray.m_closestHitFraction, reference.closest, 1e-7);
    }
    EXPECT_LT(ray.m_hitNormalWorld.dot(to - from), 0.0f);
  }

 private:
  std::shared_ptr<const BodyModel> model_;
  bullet::SdfccdShape ours_;
  btTriangleMesh triangles_;
  std::unique_ptr<btBvhTriangleMeshShape> bvh_;
  btTransform pose_;
  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_{&configuration_};
  btDbvtBroadphase broadphaseA_, broadphaseB_;
  btCollisionWorld oursWorld_{&dispatcher_, &broadphaseA_, &configuration_};
  btCollisionWorld bvhWorld_{&dispatcher_, &broadphaseB_, &configuration_};
  btCollisionObject oursObject_, bvhObject_;
};

btVector3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<float> n;
  return btVector3(n(rng), n(rng), n(rng)).normalized();
}

// Rays from a sphere around the bunny towards random points near it: hits and misses.
TEST(ShapeQueries, RandomRaysMatchTheTriangles) {
  QueryWorld w;
  std::mt19937 rng(15);
  std::uniform_real_distribution<float> u(0, 1);
  const btScalar size = btScalar(w.size());
  int hits = 0;
  for (int i = 0; i < 300; ++i) {
    const btVector3 from = w.centreWorld() + randomUnit(rng) * size;
    const btVector3 target = w.centreWorld() + randomUnit(rng) * (0.4f * size * u(rng));
    const btVector3 to = from + (target - from) * 1.6f;
    SCOPED_TRACE(i);
    w.expectSameClosestHit(from, to);
    btCollisionWorld::ClosestRayResultCallback ray(from, to);
    w.ours().rayTest(from, to, ray);
    hits += ray.hasHit();
  }
  EXPECT_GT(hits, 100);  // both kinds are exercised
  EXPECT_LT(hits, 300);
}

// A ray that starts inside the solid reports where it leaves, like the triangle mesh; back-face filtering
// then reports nothing.
TEST(ShapeQueries, RaysStartingInside) {
  QueryWorld w;
  std::mt19937 rng(16);
  const btVector3 inside = w.pose()(btVector3(0, 0, 0));  // the centre of mass
  for (int i = 0; i < 50; ++i) {
    const btVector3 to = inside + randomUnit(rng) * btScalar(w.size());
    SCOPED_TRACE(i);
    w.expectSameClosestHit(inside, to);
    w.expectSameClosestHit(inside, to, btTriangleRaycastCallback::kF_FilterBackfaces);
  }
}

// Rays grazing the surface: along a triangle's plane, just outside and just inside it, and short rays that end
// just before or after the surface.
TEST(ShapeQueries, GrazingAndShortRays) {
  QueryWorld w;
  std::mt19937 rng(17);
  const TriangleMesh& mesh = w.model().meshInBody();
  std::uniform_int_distribution<int> pick(0, static_cast<int>(mesh.triangles.size()) - 1);
  const double cell = w.model().cellSize();
  for (int i = 0; i < 150; ++i) {
    const auto& t = mesh.triangles[std::size_t(pick(rng))];
    const Vec3 a = mesh.vertices[std::size_t(t[0])], b = mesh.vertices[std::size_t(t[1])],
               c = mesh.vertices[std::size_t(t[2])];
    const Vec3 normal = (b - a).cross(c - a).normalized();
    const Vec3 centroid = (a + b + c) / 3.0;
    const Vec3 along = (b - a).normalized();
    SCOPED_TRACE(i);
    for (double offset : {-0.05 * cell, 0.0, 0.05 * cell, 0.5 * cell}) {
      const Vec3 p = centroid + offset * normal;
      w.expectSameClosestHit(w.pose()(bullet::toBtVector3(p - 3 * cell * along)), w.pose()(bullet::toBtVector3(p + 3 * cell * along)));
    }
    // Short rays along the normal, ending before and after the surface.
    for (double end : {0.01 * cell, -0.01 * cell}) {
      w.expectSameClosestHit(w.pose()(bullet::toBtVector3(centroid + 0.2 * cell * normal)),
                             w.pose()(bullet::toBtVector3(centroid + end * normal)));
    }
  }
}

// An all-hits callback sees every crossing once, as the triangle mesh reports them.
TEST(ShapeQueries, AllHitsCountsEveryCrossingOnce) {
  QueryWorld w;
  std::mt19937 rng(18);
  int multi = 0;
  for (int i = 0; i < 60; ++i) {
    const btVector3 from = w.centreWorld() + randomUnit(rng) * btScalar(w.size());
    const btVector3 to = w.centreWorld() - (from - w.centreWorld());
    btCollisionWorld::AllHitsRayResultCallback ours(from, to);
    w.ours().rayTest(from, to, ours);
    btCollisionWorld::AllHitsRayResultCallback bvh(from, to);
    w.bvh().rayTest(from, to, bvh);
    const btTransform inverse = w.pose().inverse();
    const BruteForceRay reference = bruteForce(inverse * from, inverse * to);
    EXPECT_EQ(ours.m_hitFractions.size(), reference.hits) << i;
    EXPECT_EQ(bvh.m_hitFractions.size(), reference.hits) << i;
    multi += reference.hits > 2;
  }
  EXPECT_GT(multi, 3);  // rays through the ears and the body cross more than twice
}

/// An all-hits callback that casts another ray through the same world from inside each result, as a user's
/// callback may (a probe from the hit point): the nested query must not disturb the outer one.
struct NestingAllHits : btCollisionWorld::AllHitsRayResultCallback {
  NestingAllHits(btCollisionWorld& world, const btTransform& bodyFromWorld, const btVector3& from, const btVector3& to,
                 const btVector3& probeTo)
      : AllHitsRayResultCallback(from, to), world(world), inverse(bodyFromWorld), probeTo(probeTo) {}
  btScalar addSingleResult(btCollisionWorld::LocalRayResult& result, bool normalInWorldSpace) override {
    const btVector3 hit = m_rayFromWorld.lerp(m_rayToWorld, result.m_hitFraction);
    btCollisionWorld::AllHitsRayResultCallback probe(hit, probeTo);
    world.rayTest(hit, probeTo, probe);
    nestedHits += static_cast<int>(probe.m_hitFractions.size());
    const BruteForceRay reference = bruteForce(inverse * hit, inverse * probeTo);
    nestedMismatches += static_cast<int>(probe.m_hitFractions.size()) != reference.hits;
    return AllHitsRayResultCallback::addSingleResult(result, normalInWorldSpace);
  }
  btCollisionWorld& world;
  btTransform inverse;  ///< body from world (the brute-force reference works in the body frame)
  btVector3 probeTo;
  int nestedHits = 0;
  int nestedMismatches = 0;  ///< nested rays whose crossings differ from the brute-force scan's
};

// A rayTest from inside a result callback (nested query on the same thread) leaves the outer query's answer
// unchanged: every crossing once, at the brute-force scan's fractions, and the nested rays are answered right too.
// (Each query leases its own scratch: with a shared one, the nested query would clear and regrow the outer one's
// candidate list while the outer loop iterates it, a heap-use-after-free.)
TEST(ShapeQueries, NestedRayTestFromAResultCallback) {
  QueryWorld w;
  std::mt19937 rng(20);
  int nested = 0;
  for (int i = 0; i < 30; ++i) {
    const btVector3 from = w.centreWorld() + randomUnit(rng) * btScalar(w.size());
    const btVector3 to = w.centreWorld() - (from - w.centreWorld());
    const btVector3 probeTo = w.centreWorld() + randomUnit(rng) * btScalar(w.size());
    const btTransform inverse = w.pose().inverse();
    NestingAllHits ours(w.ours(), inverse, from, to, probeTo);
    w.ours().rayTest(from, to, ours);
    BruteForceRay reference(inverse * from, inverse * to);
    std::vector<btScalar> expected;
    reference.fractions = &expected;
    scanAll(reference);
    std::vector<btScalar> got;
    for (int k = 0; k < ours.m_hitFractions.size(); ++k) got.push_back(ours.m_hitFractions[k]);
    std::sort(got.begin(), got.end());
    std::sort(expected.begin(), expected.end());
    ASSERT_EQ(got.size(), expected.size()) << i;
    for (std::size_t k = 0; k < got.size(); ++k) EXPECT_NEAR(got[k], expected[k], 1e-6) << i;
    EXPECT_EQ(ours.nestedMismatches, 0) << i;
    nested += ours.nestedHits;
  }
  EXPECT_GT(nested, 10);  // the nested rays did walk the triangles
}

// Convex sweeps (sphere, box) give the btBvhTriangleMeshShape's closest hit.
TEST(ShapeQueries, ConvexSweepsMatchTheTriangleMesh) {
  QueryWorld w;
  std::mt19937 rng(19);
  std::uniform_real_distribution<float> u(0, 1);
  const btScalar size = btScalar(w.size());
  btSphereShape sphere(0.03f * size);
  btBoxShape box(btVector3(0.04f, 0.02f, 0.03f) * size);
  int hits = 0;
  for (int i = 0; i < 80; ++i) {
    btConvexShape* shape = i % 2 == 0 ? static_cast<btConvexShape*>(&sphere) : &box;
    const btVector3 fromPoint = w.centreWorld() + randomUnit(rng) * size;
    const btVector3 target = w.centreWorld() + randomUnit(rng) * (0.4f * size * u(rng));
    // One orientation for the whole sweep: Bullet's BVH traversal boxes the shape at the end orientation only,
    // so with a turning shape it can skip triangles that our walk (a bounding sphere) hands over.
    const btQuaternion q(randomUnit(rng), u(rng) * 3);
    const btTransform from(q, fromPoint), to(q, fromPoint + (target - fromPoint) * 1.5f);
    btCollisionWorld::ClosestConvexResultCallback ours(from.getOrigin(), to.getOrigin());
    w.ours().convexSweepTest(shape, from, to, ours);
    btCollisionWorld::ClosestConvexResultCallback bvh(from.getOrigin(), to.getOrigin());
    w.bvh().convexSweepTest(shape, from, to, bvh);
    SCOPED_TRACE(i);
    ASSERT_EQ(ours.hasHit(), bvh.hasHit());
    if (!ours.hasHit()) continue;
    ++hits;
    EXPECT_NEAR(ours.m_closestHitFraction, bvh.m_closestHitFraction, 1e-5);
    // The contact point is not unique when several triangles are touched at the same fraction (the callback
    // keeps the last, and the order differs): ours must lie on the surface, within a cell of the field's zero.
    const Vec3 pointInBody = bullet::toVec3(w.pose().inverse() * ours.m_hitPointWorld);
    EXPECT_LT(std::abs(w.model().field().distance(w.model().bodyFromField().inverse() * pointInBody)),
              w.model().cellSize());
  }
  EXPECT_GT(hits, 20);
}

// The pose helpers: round trips, and the body transform that puts the mesh where its file has it.
TEST(BulletPose, RoundTripsAndTheMeshFilePose) {
  Rigid r = Rigid::Identity();
  r.linear() = Eigen::AngleAxisd(0.8, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  r.translation() = Vec3(0.1, -2.0, 3.5);
  const Rigid back = bullet::toRigid(bullet::toBtTransform(r));
  EXPECT_LT((back.matrix() - r.matrix()).norm(), 1e-6);
  EXPECT_EQ(bullet::toVec3(btVector3(1, 2, 3)), Vec3(1, 2, 3));
  const auto bunny = bunnyModel();
  // The bunny's body frame is rotated and shifted from its file's frame.
  EXPECT_GT(Eigen::AngleAxisd(bunny->modelFromBody().linear()).angle(), 0.3);
  const btTransform meshPose(btQuaternion(btVector3(0, 1, 0), 0.5f), btVector3(1, 2, 3));
  const btTransform body = bullet::bodyTransformForMeshPose(*bunny, meshPose);
  // Every vertex of the body-frame mesh lands where the file's pose puts the file's vertex (modelFromBody * v).
  const TriangleMesh& mesh = bunny->meshInBody();
  for (std::size_t i = 0; i < mesh.vertices.size(); i += 997) {
    const Vec3 inFile = bunny->modelFromBody() * mesh.vertices[i];
    const btVector3 expected = meshPose(bullet::toBtVector3(inFile));
    EXPECT_LT((body(bullet::toBtVector3(mesh.vertices[i])) - expected).length(), 1e-5f);
  }
  const btTransform again = bullet::meshPoseOfBody(*bunny, body);
  EXPECT_LT((again.getOrigin() - meshPose.getOrigin()).length(), 1e-5f);
  EXPECT_GT(again.getRotation().dot(meshPose.getRotation()), 1 - 1e-6f);
}

}  // namespace queries_test
}  // namespace sdfccd
