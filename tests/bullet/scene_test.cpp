// Scenes in Bullet: effects that are not listed cost nothing, and determinism. (Reading and validating scene
// files: tests/model/scene_reader_test.cpp.)
#include <gtest/gtest.h>

#include <string>

#include "bullet_test_util.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/error.h"

namespace sdfccd {
namespace {

const char* kBody = R"({ "primitive": { "type": "box", "half_extents": [0.1, 0.1, 0.1] }, "mass": 1.0 })";

std::string withBody(const std::string& top, const std::string& body = kBody) {
  return "{ " + top + (top.empty() ? "" : ", ") + "\"bodies\": [" + body + "] }";
}

TEST(Scene, EffectsNotListedAreNotComputed) {
  const Scene plain = test::sceneFromText(withBody("\"effects\": [\"ground\"]"));
  const bullet::ContactSettings s = bullet::contactSettingsFor(plain);
  EXPECT_FALSE(s.penalty.enableDamping);
  EXPECT_FALSE(s.penalty.enableRotation);
  EXPECT_EQ(plain.effectList(), "ground");
  // No gravity effect: nothing falls.
  bullet::SceneWorld world(test::sceneFromText(withBody("\"effects\": [\"ground\"]", R"({ "primitive": { "type": "box",
      "half_extents": [0.1, 0.1, 0.1] }, "mass": 1.0, "position": [0, 1, 0], "resolution": 8, "points": 50 })")));
  for (int f = 0; f < 20; ++f) world.step();
  EXPECT_EQ(world.bodyState(0).position.y(), 1.0);
  const Scene all = test::sceneFromText(withBody("\"effects\": [\"rotation\", \"damping\", \"gravity\"]"));
  EXPECT_TRUE(bullet::contactSettingsFor(all).penalty.enableDamping);
  EXPECT_TRUE(bullet::contactSettingsFor(all).penalty.enableRotation);
}

// The same scene twice gives the same final state, bit for bit.
TEST(Scene, DeterministicResultHash) {
  const std::string text = R"({
    "timestep": 0.001, "frames": 250, "effects": ["gravity", "ground", "damping", "rotation"],
    "contact": { "mode": "penalty", "stiffness": 2000.0, "damping": 3.0 },
    "bodies": [
      { "name": "a", "primitive": { "type": "box", "half_extents": [0.05, 0.03, 0.04] }, "mass": 1.0,
        "position": [0, 0.08, 0], "orientation": [0.9238795325112867, 0.3826834323650898, 0, 0],
        "angular_velocity": [1, 2, 0], "points": 200, "resolution": 12 },
      { "name": "b", "primitive": { "type": "sphere", "radius": 0.04, "subdivisions": 2 }, "mass": 0.5,
        "position": [0.01, 0.2, 0], "points": 150, "resolution": 12 } ] })";
  std::uint64_t hashes[2];
  for (int run = 0; run < 2; ++run) {
    bullet::SceneWorld world(test::sceneFromText(text));
    for (int f = 0; f < 250; ++f) world.step();
    hashes[run] = world.stateHash();
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

// A constraint solver asked for in C++ where the scene runs penalty mode is refused, as the scene key is.
TEST(Scene, SolverOverrideInPenaltyModeIsRefused) {
  bullet::SceneWorldSettings settings;
  settings.solver = ContactSolver::Mlcp;
  const Scene penalty = test::sceneFromText(withBody("\"contact\": { \"mode\": \"penalty\" }"));
  try {
    bullet::SceneWorld world(penalty, settings);
    FAIL() << "penalty mode accepted a constraint solver";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("solver mode"), std::string::npos) << e.what();
  }
  const Scene solver = test::sceneFromText(withBody("\"contact\": { \"mode\": \"solver\" }"));
  EXPECT_NO_THROW(bullet::SceneWorld(solver, settings));
}

}  // namespace
}  // namespace sdfccd
