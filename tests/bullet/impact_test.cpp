// Fast impacts: a body shot at a thin plate tunnels with the discrete model and is stopped by the continuous
// model with time-of-impact clamping; two free bodies collide without gravity and conserve momentum.
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include "bullet_test_util.h"
#include "sdfccd/bullet/scene_world.h"

namespace sdfccd {
namespace {

// A ball (r = 5 cm) at 40 m/s towards a 3 cm plate: 4 cm per step of 1 ms.
const char* kPlateScene = R"({
  "timestep": 0.001, "frames": 40, "effects": ["damping", "rotation"],
  "contact": { "mode": "penalty", "model": "continuous", "stiffness": 2000.0, "damping": 2.0 },
  "bodies": [
    { "name": "plate", "primitive": { "type": "box", "half_extents": [0.15, 0.015, 0.15] }, "static": true,
      "points": 400, "resolution": 40 },
    { "name": "ball", "primitive": { "type": "sphere", "radius": 0.05, "subdivisions": 3 }, "mass": 1.0,
      "position": [0.0, 0.3, 0.0], "velocity": [0.0, -40.0, 0.0], "points": 300, "resolution": 16 } ] })";

TEST(Impact, ThinPlateContinuousDoesNotTunnel) {
  bullet::SceneWorld world(test::sceneFromText(kPlateScene));
  for (int f = 0; f < 40; ++f) world.step();
  EXPECT_TRUE(world.tunneledBodies().empty());
  EXPECT_GT(world.bodyState(1).position.y(), 0.015);  // above the plate
  EXPECT_GT(world.clamps(), 0);
  EXPECT_FALSE(world.hasNonFinite());
}

TEST(Impact, ThinPlateDiscreteTunnels) {
  bullet::SceneWorldSettings settings;
  settings.model = PenaltyModel::Discrete;
  bullet::SceneWorld world(test::sceneFromText(kPlateScene), settings);
  for (int f = 0; f < 40; ++f) world.step();
  ASSERT_EQ(world.tunneledBodies().size(), 1u);
  EXPECT_EQ(world.tunneledBodies()[0], "ball");
  EXPECT_LT(world.bodyState(1).position.y(), -0.015);
}

// Two balls of different masses meet head on, off centre (rotation on): total linear momentum is kept
// (every impulse acts on both bodies with opposite signs).
TEST(Impact, FreeBodiesConserveLinearMomentum) {
  const Scene scene = test::sceneFromText(R"({
    "timestep": 0.001, "frames": 200, "effects": ["damping", "rotation"],
    "contact": { "mode": "penalty", "stiffness": 3000.0, "damping": 1.0 },
    "bodies": [
      { "name": "a", "primitive": { "type": "sphere", "radius": 0.05, "subdivisions": 3 }, "mass": 1.0,
        "position": [-0.12, 0.0, 0.0], "velocity": [1.0, 0.0, 0.0], "points": 300, "resolution": 16 },
      { "name": "b", "primitive": { "type": "box", "half_extents": [0.04, 0.05, 0.05] }, "mass": 2.0,
        "position": [0.12, 0.02, 0.0], "velocity": [-0.5, 0.1, 0.0], "points": 300, "resolution": 16 } ] })");
  bullet::SceneWorld world(scene);
  const Vec3 before = 1.0 * world.bodyState(0).linearVelocity + 2.0 * world.bodyState(1).linearVelocity;
  int contactFrames = 0;
  for (int f = 0; f < scene.frames; ++f) {
    world.step();
    contactFrames += world.lastFrame().contacts > 0 ? 1 : 0;
  }
  const Vec3 after = 1.0 * world.bodyState(0).linearVelocity + 2.0 * world.bodyState(1).linearVelocity;
  EXPECT_GT(contactFrames, 3);
  EXPECT_LT((after - before).norm(), 1e-4 * before.norm());
  // They did interact: the light ball bounced back or slowed down.
  EXPECT_LT(world.bodyState(0).linearVelocity.x(), 0.9);
}

}  // namespace
}  // namespace sdfccd
