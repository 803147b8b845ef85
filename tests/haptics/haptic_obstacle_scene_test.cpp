/// @file
/// @brief The scene format's "obstacles" list and the tool's "field" (docs/scene-format.md): the Fig. 7
/// scenes load with the paper's roles, and the strict reader rejects bad obstacles with one line naming the key.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>

#include "haptics/haptic_test_scenes.h"
#include "sdfccd/error.h"
#include "sdfccd/haptics/haptic_scene.h"
#include "sdfccd/haptics/haptic_session.h"
#include "sdfccd/haptics/procedural_shapes.h"

namespace sdfccd::haptics {
namespace {

TEST(HapticObstacleScene, Fig7PegIsTheToolFieldAndTheHoleA6691PointShell) {
  const HapticScene scene = loadHapticScene(test::scenePath("peg-in-hole-fig7.json"));
  ASSERT_EQ(scene.obstacles.size(), 1u);
  const HapticObstacle& hole = scene.obstacles[0];
  ASSERT_TRUE(hole.isShell());
  EXPECT_EQ(hole.shell->pointCount(), 6691);
  EXPECT_FALSE(hole.path.moving());
  EXPECT_FALSE(scene.grid);
  EXPECT_FALSE(scene.plane);
  ASSERT_TRUE(scene.toolField);
  // 64 cells along the peg's 30 mm height.
  EXPECT_NEAR(scene.toolField->grid().spacing(), 0.03 / 64, 1e-9);
  EXPECT_EQ(scene.cellSize, scene.toolField->grid().spacing());
  // The peg's field halfway between its axis and its side: -4 mm (the 96-gon's faces are 8 (1 - 0.0005) mm out).
  EXPECT_NEAR(scene.toolField->distance(Vec3(0.004, 0.0, 0.0)), -0.004, 0.05 * scene.cellSize);
  // Every point of the hole's wall lies between the polygon's faces and its circle, 8.036-8.04 mm from the axis.
  int wall = 0;
  for (const Vec3& p : hole.shell->shell().positions) {
    const double radial = std::hypot(p.x(), p.z());
    if (radial < 0.009 && std::abs(p.y()) < 0.015 - 1e-9) {
      ++wall;
      EXPECT_GE(radial, 0.00804 * std::cos(std::acos(-1.0) / 96) - 1e-9);
      EXPECT_LE(radial, 0.00804 + 1e-9);
    }
  }
  EXPECT_GT(wall, 500);
}

TEST(HapticObstacleScene, BlockWithHoleIsClosedAndOutwardOriented) {
  const TriangleMesh mesh = blockWithHole(Vec3(0.02, 0.015, 0.03), 0.008, 20);  // a corner between rays, too
  const double pi = std::acos(-1.0);
  // The volume of the block less the 20-gon prism (area (n/2) r^2 sin(2 pi / n)).
  const double expected = 8 * 0.02 * 0.015 * 0.03 - 10 * 0.008 * 0.008 * std::sin(2 * pi / 20) * 0.03;
  EXPECT_NEAR(mesh.signedVolume(), expected, 1e-12);
  EXPECT_THROW(blockWithHole(Vec3(0.02, 0.015, 0.02), 0.02, 32), Error);
}

/// Loads `text` from a scratch file; returns the error's message ("" when it loads). The file is named after the
/// running test: ctest runs this file's tests as processes in parallel, and a shared name let one test remove or
/// overwrite the other's scene mid-load (the process id: two builds' suites may run at once).
std::string loadError(const std::string& text) {
  const std::string path = ::testing::TempDir() + "haptic_obstacle_scene_test_" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
                           std::to_string(::getpid()) + ".json";
  {
    std::ofstream out(path);
    out << text;
  }
  try {
    loadHapticScene(path);
  } catch (const Error& e) {
    std::remove(path.c_str());
    return e.what();
  }
  std::remove(path.c_str());
  return "";
}

/// A small scene around `obstacles` (its JSON text) and the tool's `extraShell` keys.
std::string scene(const std::string& obstacles, const std::string& extraShell = "") {
  return R"({"obstacles": )" + obstacles + R"(, "shell": {"shape": "box", "halfExtents": [0.01, 0.01, 0.01],
    "points": 40, "iterations": 1)" +
         extraShell + R"(}, "start": {"position": [0, 0, 0]},
    "script": [{"t": 0, "position": [0, 0, 0]}]})";
}

TEST(HapticObstacleScene, ReaderAcceptsFieldsShellsPosesAndPaths) {
  const std::string plane = R"({"plane": {"normal": [1, 0, 0]}, "pose": {"position": [-0.03, 0, 0]}})";
  const std::string moving = R"({"name": "pusher", "plane": {"normal": [-1, 0, 0]},
    "path": [{"t": 0, "position": [0.03, 0, 0]}, {"t": 1, "position": [0.02, 0, 0]}]})";
  const std::string shell = R"({"shell": {"shape": "sphere", "radius": 0.005, "subdivisions": 1, "points": 30,
    "iterations": 1}, "pose": {"position": [0, 0.02, 0]}})";
  EXPECT_EQ(loadError(scene("[" + plane + ", " + moving + ", " + shell + "]",
                            R"(, "field": {"resolution": 8, "padding": 2})")),
            "");
}

TEST(HapticObstacleScene, ReaderNamesTheBadKey) {
  const auto expectError = [](const std::string& text, const std::string& key) {
    const std::string message = loadError(text);
    EXPECT_NE(message.find(key), std::string::npos) << "'" << message << "' does not name " << key;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  };
  const std::string plane = R"("plane": {"normal": [1, 0, 0]})";
  expectError(scene("[{" + plane + R"(, "colour": 1}])"), "obstacles[0]");
  expectError(scene("[{" + plane + R"(, "pose": {"position": [0, 0, 0], "scale": 2}}])"), "obstacles[0].pose");
  expectError(scene("[{" + plane + R"(, "path": [{"t": 1, "position": [0, 0, 0]}, {"t": 0, "position": [0, 0, 0]}]}])"),
              "obstacles[0].path");
  expectError(scene("[{" + plane + R"(, "pose": {"position": [0, 0, 0]}, "path": [{"t": 0, "position": [0, 0, 0]}]}])"),
              "obstacles[0].path");
  expectError(scene(R"([{"shell": {"shape": "sphere", "radius": 0.005, "points": 30, "iterations": 1}}])"),
              "obstacles[0].shell");
  expectError(scene(R"([{"shell": {"shape": "block-with-hole", "halfExtents": [0.01, 0.01, 0.01], "holeRadius": 0.02,
    "points": 30, "iterations": 1}}])",
                    R"(, "field": {"resolution": 8})"),
              "obstacles[0].shell.holeRadius");
  expectError(scene("[]"), "obstacles");
  expectError(scene("[{" + plane + "}]", R"(, "field": {"resolution": 1})"), "shell.field.resolution");
  const std::string both = scene("[{" + plane + "}]");
  expectError(R"({"obstacle": {)" + plane + "}, " + both.substr(1), "obstacles");
}

}  // namespace
}  // namespace sdfccd::haptics

namespace sdfccd::haptics {
namespace {

/// The largest x the simulated object reached in a run.
double farthestX(const HapticSessionResult& r) {
  double x = -1e300;
  for (const HapticTickRecord& t : r.ticks) x = std::max(x, t.worldFromSimulation.translation().x());
  return x;
}

TEST(HapticObstacleScene, MovingWallSceneRunsWithBothMethods) {
  const HapticScene scene = loadHapticScene(test::scenePath("moving-wall.json"));
  ASSERT_EQ(scene.obstacles.size(), 2u);
  EXPECT_TRUE(scene.obstacles[1].path.moving());
  HapticSessionSettings s;
  s.method = HapticMethod::Constraint;
  const HapticSessionResult constraint = runHapticSession(scene, s);
  EXPECT_EQ(constraint.summary.error, "");
  EXPECT_EQ(constraint.summary.runaway, "");
  EXPECT_EQ(constraint.summary.maxPenetrationCells, 0.0);
  // Pushed until the wall stops at x = 20 mm: the box's centre 10 mm further, on the wall's contact level set.
  const double sigma = scene.god.sigma;
  EXPECT_NEAR(farthestX(constraint), 0.03 + sigma, scene.god.contactThreshold);
  // The wall went back: the user's spring brings the box back to the origin.
  EXPECT_NEAR(constraint.summary.finalPosition.x(), 0.0, 0.002);
  s.method = HapticMethod::Penalty;
  const HapticSessionResult penalty = runHapticSession(scene, s);
  EXPECT_EQ(penalty.summary.error, "");
  EXPECT_EQ(penalty.summary.runaway, "");
  EXPECT_LT(penalty.summary.maxPenetrationCells, 0.5);
  EXPECT_NEAR(farthestX(penalty), 0.03, 0.5 * scene.cellSize);
  EXPECT_NEAR(penalty.summary.finalPosition.x(), 0.0, 0.002);
}

}  // namespace
}  // namespace sdfccd::haptics
