// Scenes: strict validation (one-line errors), effects that are not listed cost nothing, determinism, and
// the shipped scene files parse.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "bullet_test_util.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/error.h"

namespace sdfccd {
namespace {

std::string errorOf(const std::string& text) {
  try {
    test::sceneFromText(text);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const char* kBody = R"({ "primitive": { "type": "box", "half_extents": [0.1, 0.1, 0.1] }, "mass": 1.0 })";

std::string withBody(const std::string& top, const std::string& body = kBody) {
  return "{ " + top + (top.empty() ? "" : ", ") + "\"bodies\": [" + body + "] }";
}

TEST(Scene, BadScenesFailWithOneLine) {
  const std::string cases[][2] = {
      {withBody("\"timestep\": 0.001, \"colour\": 3"), "colour"},
      {withBody("", R"({ "primitive": { "type": "box" }, "mass": -1.0 })"), "mass"},
      {withBody("", R"({ "primitive": { "type": "box" }, "mass": 0.0 })"), "mass"},
      {withBody("", R"({ "primitive": { "type": "box" } })"), "mass"},
      {withBody("", R"({ "mesh": "meshes/no-such-mesh.off", "mass": 1.0 })"), "missing file"},
      {withBody("", R"({ "primitive": { "type": "box" }, "mass": 1.0, "orientation": [1, 0.1, 0, 0] })"),
       "unit quaternion"},
      {withBody("", R"({ "primitive": { "type": "box" }, "mass": 1.0, "position": [0, 1e999, 0] })"), "JSON"},
      {withBody("", R"({ "primitive": { "type": "box" }, "mass": 1.0, "spin": 2 })"), "spin"},
      {withBody("\"effects\": [\"gravity\", \"magnetism\"]"), "magnetism"},
      {withBody("\"timestep\": -0.01"), "timestep"},
      {withBody("\"contact\": { \"model\": \"implicit\" }"), "contact.model"},
      {"{ \"bodies\": [] }", "bodies"},
      {"{ \"timestep\": 0.001, ", "JSON"},
      {"{ \"timestep\": NaN, \"bodies\": [] }", "JSON"},
  };
  for (const auto& c : cases) {
    const std::string message = errorOf(c[0]);
    EXPECT_NE(message.find(c[1]), std::string::npos) << "scene: " << c[0] << "\nmessage: " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_EQ(errorOf(withBody("\"effects\": [\"gravity\"]")), "");
}

TEST(Scene, EffectsNotListedAreNotComputed) {
  const Scene plain = test::sceneFromText(withBody("\"effects\": [\"ground\"]"));
  const SdfccdContactSettings s = contactSettingsFor(plain);
  EXPECT_FALSE(s.penalty.enableDamping);
  EXPECT_FALSE(s.penalty.enableRotation);
  EXPECT_EQ(plain.effectList(), "ground");
  // No gravity effect: nothing falls.
  SceneWorld world(test::sceneFromText(withBody("\"effects\": [\"ground\"]", R"({ "primitive": { "type": "box",
      "half_extents": [0.1, 0.1, 0.1] }, "mass": 1.0, "position": [0, 1, 0], "resolution": 8, "points": 50 })")));
  for (int f = 0; f < 20; ++f) world.step();
  EXPECT_EQ(world.bodyState(0).position.y(), 1.0);
  const Scene all = test::sceneFromText(withBody("\"effects\": [\"rotation\", \"damping\", \"gravity\"]"));
  EXPECT_TRUE(contactSettingsFor(all).penalty.enableDamping);
  EXPECT_TRUE(contactSettingsFor(all).penalty.enableRotation);
}

// The same scene twice gives the same final state, bit for bit.
TEST(Scene, DeterministicResultHash) {
  const std::string text = R"({
    "timestep": 0.001, "frames": 250, "effects": ["gravity", "ground", "damping", "rotation"],
    "contact": { "stiffness": 2000.0, "damping": 3.0 },
    "bodies": [
      { "name": "a", "primitive": { "type": "box", "half_extents": [0.05, 0.03, 0.04] }, "mass": 1.0,
        "position": [0, 0.08, 0], "orientation": [0.9238795325112867, 0.3826834323650898, 0, 0],
        "angular_velocity": [1, 2, 0], "points": 200, "resolution": 12 },
      { "name": "b", "primitive": { "type": "sphere", "radius": 0.04, "subdivisions": 2 }, "mass": 0.5,
        "position": [0.01, 0.2, 0], "points": 150, "resolution": 12 } ] })";
  std::uint64_t hashes[2];
  for (int run = 0; run < 2; ++run) {
    SceneWorld world(test::sceneFromText(text));
    for (int f = 0; f < 250; ++f) world.step();
    hashes[run] = world.stateHash();
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(Scene, ShippedScenesParse) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(SDFCCD_ASSETS_DIR) + "/scenes")) {
    if (entry.path().extension() != ".json") continue;
    EXPECT_NO_THROW(loadScene(entry.path().string())) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 5);
}

}  // namespace
}  // namespace sdfccd
