// Non-finite state (beside the hard cases of stability_test.cpp): NaN or infinite values in a
// Scene built in code, or injected into the world between steps, are rejected with one line naming the body and
// the field, and the contact system never spreads them to another body.
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "bullet_test_util.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/error.h"

namespace sdfccd {
namespace nonfinite_state_test {
// NaN or infinite state in a Scene built in code (the parser rejects it in files: scene_test.cpp) is
// rejected when the world is built, with one line naming the body and the field.
TEST(Stability, NonFiniteSceneStateIsRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const Scene good = test::sceneFromText(
      R"({ "effects": ["gravity", "ground"], "bodies": [
           { "name": "first", "primitive": { "type": "box", "half_extents": [0.1, 0.1, 0.1] }, "mass": 1.0,
             "position": [0, 0.5, 0], "points": 0, "resolution": 8 },
           { "name": "second", "primitive": { "type": "box", "half_extents": [0.1, 0.1, 0.1] }, "mass": 1.0,
             "position": [0, 1.5, 0], "points": 0, "resolution": 8 } ] })");
  struct Case {
    const char* expected;
    void (*spoil)(Scene&, double);
    double value;
  };
  const Case cases[] = {
      {"'second' (bodies[1]): position", [](Scene& s, double v) { s.bodies[1].position.y() = v; }, nan},
      {"'second' (bodies[1]): position", [](Scene& s, double v) { s.bodies[1].position.x() = v; }, -inf},
      {"'second' (bodies[1]): velocity", [](Scene& s, double v) { s.bodies[1].velocity.z() = v; }, inf},
      {"'first' (bodies[0]): angular velocity", [](Scene& s, double v) { s.bodies[0].angularVelocity.x() = v; }, nan},
      {"'first' (bodies[0]): orientation", [](Scene& s, double v) { s.bodies[0].orientation.w() = v; }, nan},
      {"'first' (bodies[0]): mass", [](Scene& s, double v) { s.bodies[0].mass = v; }, nan},
      {"'first' (bodies[0]): mass", [](Scene& s, double v) { s.bodies[0].mass = v; }, inf},
      {"'first' (bodies[0]): mass", [](Scene& s, double v) { s.bodies[0].mass = v; }, 0.0},
      {"'first' (bodies[0]): mass", [](Scene& s, double v) { s.bodies[0].mass = v; }, -1.0},
      {"timestep", [](Scene& s, double v) { s.timestep = v; }, nan},
      {"timestep", [](Scene& s, double v) { s.timestep = v; }, inf},
      {"gravity", [](Scene& s, double v) { s.gravity.y() = v; }, nan},
  };
  for (const Case& c : cases) {
    Scene bad = good;
    c.spoil(bad, c.value);
    test::expectOneLineError([&] { bullet::SceneWorld world(bad); }, c.expected, " = " + std::to_string(c.value));
  }
  bullet::SceneWorldSettings settings;
  settings.timestep = nan;
  EXPECT_THROW(bullet::SceneWorld(good, settings), Error);
}

// A small box resting on a larger one on the ground (bodies "bottom" and "top"), no sleeping.
Scene smallBoxOnLargeBox() {
  return test::sceneFromText(
      R"({ "effects": ["gravity", "ground", "damping", "rotation"], "sleeping": false,
           "contact": { "mode": "penalty" }, "bodies": [
           { "name": "bottom", "primitive": { "type": "box", "half_extents": [0.15, 0.05, 0.15] }, "mass": 1.0,
             "position": [0, 0.05, 0], "points": 0, "resolution": 12 },
           { "name": "top", "primitive": { "type": "box", "half_extents": [0.05, 0.05, 0.05] }, "mass": 1.0,
             "position": [0, 0.149, 0], "points": 0, "resolution": 12 } ] })");
}

// NaN or infinite state set on a body between steps (Bullet's setters) is rejected by the next step with one
// line naming the body and the field; the step does not run, so no other body sees it.
TEST(Stability, NonFiniteStateInjectedBetweenStepsIsRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const Scene scene = smallBoxOnLargeBox();
  struct Case {
    const char* expected;
    void (*inject)(btRigidBody&, double);
    double value;
  };
  const Case cases[] = {
      {"'top' (bodies[1]) has a non-finite position",
       [](btRigidBody& b, double v) {
         btTransform t = b.getWorldTransform();
         t.getOrigin().setY(btScalar(v));
         b.setWorldTransform(t);
       },
       nan},
      {"'top' (bodies[1]) has a non-finite orientation",
       [](btRigidBody& b, double v) {
         btTransform t = b.getWorldTransform();
         t.setRotation(btQuaternion(btScalar(v), 0, 0, 1));
         b.setWorldTransform(t);
       },
       nan},
      {"'top' (bodies[1]) has a non-finite linear velocity",
       [](btRigidBody& b, double v) { b.setLinearVelocity(btVector3(0, btScalar(v), 0)); }, inf},
      {"'top' (bodies[1]) has a non-finite angular velocity",
       [](btRigidBody& b, double v) { b.setAngularVelocity(btVector3(btScalar(v), 0, 0)); }, nan},
      {"'top' (bodies[1]) has a non-finite mass",
       [](btRigidBody& b, double v) { b.setMassProps(btScalar(v), btVector3(1, 1, 1)); }, nan},
      {"'top' (bodies[1]) has a non-finite applied force",
       [](btRigidBody& b, double v) { b.applyCentralForce(btVector3(btScalar(v), 0, 0)); }, inf},
  };
  for (const Case& c : cases) {
    bullet::SceneWorld world(scene);
    for (int f = 0; f < 50; ++f) world.step();
    const bullet::SceneBodyState bottomBefore = world.bodyState(0);
    c.inject(world.body(1), c.value);
    test::expectOneLineError([&] { world.step(); }, c.expected);
    EXPECT_EQ(world.frame(), 50);
    const bullet::SceneBodyState bottomAfter = world.bodyState(0);
    EXPECT_EQ(bottomAfter.position, bottomBefore.position) << c.expected;
    EXPECT_EQ(bottomAfter.linearVelocity, bottomBefore.linearVelocity) << c.expected;
  }
}

// A Bullet user who steps the world directly (no SceneWorld check) with a NaN velocity on one body: the
// contact system gives that body no contact, so the NaN never reaches the body under it.
TEST(Stability, ContactSystemDoesNotSpreadNonFiniteState) {
  const Scene scene = smallBoxOnLargeBox();
  bullet::SceneWorld world(scene);
  for (int f = 0; f < 50; ++f) world.step();
  ASSERT_GT(world.lastFrame().contacts, 0);
  world.body(1).setLinearVelocity(btVector3(std::numeric_limits<btScalar>::quiet_NaN(), 0, 0));
  for (int f = 0; f < 5; ++f) world.world().stepSimulation(btScalar(0.001), 0);
  EXPECT_GT(world.contacts().statistics().nonFinitePairs, 0);
  const bullet::SceneBodyState bottom = world.bodyState(0);
  EXPECT_TRUE(bottom.position.allFinite() && bottom.linearVelocity.allFinite() && bottom.angularVelocity.allFinite());
}

}  // namespace nonfinite_state_test
}  // namespace sdfccd
