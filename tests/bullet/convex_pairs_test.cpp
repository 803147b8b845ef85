// Bullet's convex shapes against ours (beyond the paper; registration: registration_test.cpp): a bunny dropped
// on a static btBoxShape rests on its top; a btSphereShape and a btCapsuleShape dropped on a static body of ours
// rest on it at the analytic height.
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "bullet_test_util.h"
#include "bullet_world_fixture.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "sdfccd/mesh/procedural_meshes.h"

namespace sdfccd {
namespace {

/// A small dynamics world with our algorithms registered (penalty contact as in the shipped drop scenes).
struct ConvexWorld : test::BulletTestWorld {
  using BulletTestWorld::BulletTestWorld;
  void run(int steps) { step(steps, 0.001); }
};

bullet::ContactSettings dropSettings() {
  bullet::ContactSettings s;
  s.mode = SdfccdContactMode::Penalty;
  s.penalty = PenaltySettings{};  // the paper's per-point law, as the shipped drop scenes name it
  s.penalty.stiffness = 10000.0;
  s.penalty.damping = 5.0;
  s.penalty.enableFriction = true;
  s.penalty.friction = 0.5;
  s.convexPointSpacingCells = 2.0;
  return s;
}

std::shared_ptr<const BodyModel> boxModel(const Vec3& halfExtents, int points = 600) {
  return BodyModel::buildFromMesh(makeBox(halfExtents), test::smallModelSettings(32, points));
}

// The bunny (0.2 m) falls 2 cm onto a static 1.2 x 0.1 x 1.2 m btBoxShape whose top is at y = 0.15 and comes
// to rest on it: its lowest shell point is at the top, within the penetration that carries its weight (a
// fraction of a cell), and it stays over the box. Our shell meets the BoxField, the box's points our field.
TEST(ConvexPairs, BunnyRestsOnStaticBulletBox) {
  // 1500 points: fewer on this coarse a shell leave the bunny rocking on three or four of them.
  const auto bunny = test::buildTestBunny(1500);
  ConvexWorld w(dropSettings());
  w.add(std::make_unique<btBoxShape>(btVector3(0.6f, 0.05f, 0.6f)), 0.0, Vec3(0, 0.1, 0));
  const double top = 0.15;
  const double lowest = -bunny->boundsInBody().min().y();
  btRigidBody& body = w.add(std::make_unique<bullet::SdfccdShape>(bunny), 1.0, Vec3(0.02, top + lowest + 0.02, -0.03));
  double deepestCells = 0.0;
  bool shellRole = false, boxRole = false;  // our shell in the box's field, the box's points in our field
  for (int i = 0; i < 2500; ++i) {
    w.run(1);
    deepestCells = std::max(deepestCells, w.contacts->lastStepMaxPenetrationCells());
    for (const bullet::PairContact& c : w.contacts->lastStepContacts()) {
      shellRole = shellRole || c.shellObject == &body;
      boxRole = boxRole || c.fieldObject == &body;
    }
  }
  const btTransform& pose = body.getWorldTransform();
  double lowestY = 1e9;
  for (const Vec3& p : bunny->shell().positions) {
    lowestY = std::min(lowestY, double(pose(btVector3(btScalar(p.x()), btScalar(p.y()), btScalar(p.z()))).y()));
  }
  const double cell = bunny->cellSize();
  EXPECT_LE(lowestY, top + 0.05 * cell) << "floating above the box";
  EXPECT_GT(lowestY, top - 0.5 * cell) << "sunk into the box";
  EXPECT_LT(bullet::toVec3(body.getLinearVelocity()).norm(), 0.02);
  EXPECT_LT(std::abs(pose.getOrigin().x()), 0.3);
  EXPECT_LT(std::abs(pose.getOrigin().z()), 0.3);
  EXPECT_GT(w.contacts->lastStepContactCount(), 0);
  EXPECT_LT(deepestCells, 1.0);
  EXPECT_TRUE(shellRole);
  EXPECT_TRUE(boxRole);
  EXPECT_EQ(w.contacts->statistics().unsupportedPairs, 0);
}

// A btSphereShape (r = 5 cm, 1 kg) dropped onto a static box of ours (top at y = 0.05) rests with its centre
// at y = 0.05 + r, less the penetration that carries its weight (a fraction of the box field's cell).
TEST(ConvexPairs, BulletSphereRestsOnStaticBodyOfOurs) {
  auto plate = boxModel(Vec3(0.3, 0.05, 0.3), 3000);
  ConvexWorld w(dropSettings());
  btRigidBody& box = w.add(std::make_unique<bullet::SdfccdShape>(plate), 0.0, Vec3::Zero());
  const double r = 0.05;
  btRigidBody& ball = w.add(std::make_unique<btSphereShape>(btScalar(r)), 1.0, Vec3(0.01, 0.2, 0.02));
  w.run(1200);
  const Vec3 at = bullet::toVec3(ball.getWorldTransform().getOrigin());
  const double cell = plate->cellSize();
  EXPECT_NEAR(at.y(), 0.05 + r - 0.25 * cell, 0.25 * cell) << "cell " << cell;
  // At rest vertically; sideways it may roll slowly (a ball on a bed of points has no rolling resistance).
  EXPECT_LT(std::abs(ball.getLinearVelocity().y()), 0.005);
  EXPECT_LT(bullet::toVec3(ball.getLinearVelocity()).norm(), 0.05);
  EXPECT_LT(std::hypot(at.x() - 0.01, at.z() - 0.02), 0.03);
  EXPECT_TRUE(bullet::toVec3(box.getWorldTransform().getOrigin()).isZero(0.0));
  EXPECT_GT(w.contacts->lastStepContactCount(), 0);
}

// A capsule lying on its side (axis x) dropped on a static box of ours rests at y = 0.05 + r.
TEST(ConvexPairs, BulletCapsuleRestsOnStaticBodyOfOurs) {
  auto plate = boxModel(Vec3(0.3, 0.05, 0.3));
  ConvexWorld w(dropSettings());
  w.add(std::make_unique<bullet::SdfccdShape>(plate), 0.0, Vec3::Zero());
  const double r = 0.04;
  btRigidBody& capsule = w.add(std::make_unique<btCapsuleShapeX>(btScalar(r), btScalar(0.2)), 1.0, Vec3(0, 0.2, 0));
  w.run(1200);
  const Vec3 at = bullet::toVec3(capsule.getWorldTransform().getOrigin());
  EXPECT_NEAR(at.y(), 0.05 + r - 0.25 * plate->cellSize(), 0.25 * plate->cellSize());
  EXPECT_LT(bullet::toVec3(capsule.getLinearVelocity()).norm(), 0.02);
}

}  // namespace
}  // namespace sdfccd
