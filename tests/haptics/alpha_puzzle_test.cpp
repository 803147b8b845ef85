/// @file
/// @brief The alpha puzzle scene (paper Section 5) in its test variant (assets/scenes/haptics/alpha-puzzle-small.json:
/// 128-cell field, 3,000 points): the pieces start interlocked and apart; the constraint method pulls one against
/// the other's loop and slides along the tube with zero penetration; the scene file's pose frame and field cache.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/haptics/haptic_session.h"
#include "sdfccd/mesh/mass_properties.h"
#include "sdfccd/model/alpha_puzzle_piece.h"

namespace sdfccd::haptics {
namespace {

std::string scenePath(const std::string& name) {
  return std::string(SDFCCD_ASSETS_DIR) + "/scenes/haptics/" + name;
}

// Smallest field value over the shell at a body pose.
double closestApproach(const HapticScene& scene, const Rigid& worldFromBody) {
  const Rigid sdfFromBody = scene.worldFromSdf.inverse() * worldFromBody;
  double nearest = 1e300;
  for (const Vec3& p : scene.tree->shell().positions)
    nearest = std::min(nearest, scene.grid->distance(sdfFromBody * p));
  return nearest;
}

TEST(AlphaPuzzleScene, PiecesStartInterlockedAndApart) {
  const HapticScene scene = loadHapticScene(scenePath("alpha-puzzle-small.json"));
  ASSERT_TRUE(scene.grid);
  EXPECT_EQ(scene.tree->pointCount(), 3000);
  EXPECT_NEAR(scene.cellSize, 0.098 / 128.0, 0.001 / 128.0);  // the piece is 4.9 generator units long in y
  // poseFrame "mesh": the start pose places the mesh frame, so the shell's points are the interlocked piece's.
  const Rigid interlocked = alphaPuzzleInterlockedPose();
  const double gap = closestApproach(scene, scene.worldFromBodyStart);
  // Curves 0.39 apart, tubes 2 * 0.15: a gap of 0.09 generator units = 1.8 mm (at scale 0.02).
  EXPECT_GT(gap, 0.0015);
  EXPECT_LT(gap, 0.0021);
  // The static field sees the moving piece's tip (inside the static loop's hole) as outside, and its own
  // tube as inside.
  const Vec3 secondTip = 0.02 * (interlocked * Vec3(-1.0, 0.0, 0.0));
  EXPECT_GT(scene.grid->distance(secondTip), 0.003);
  EXPECT_LT(scene.grid->distance(0.02 * Vec3(-1.0, 0.0, 0.0)), -0.002);
  // The moving piece's body frame is the mesh's frame moved to its centre of mass: the start pose is the
  // interlocked pose (scaled to metres) with that offset.
  TriangleMesh piece = makeAlphaPuzzlePiece();
  for (Vec3& v : piece.vertices) v *= 0.02;
  const Vec3 com = computeMassProperties(piece, MassPropertiesSettings{0.0, 0.05}).centerOfMassInMesh;
  const Vec3 expected = interlocked.linear() * com + 0.02 * interlocked.translation();
  EXPECT_LT((scene.worldFromBodyStart.translation() - expected).norm(), 1e-12);
  EXPECT_LT((scene.worldFromBodyStart.linear() - interlocked.linear()).norm(), 1e-12);
}

TEST(AlphaPuzzleScene, ConstraintMethodSlidesAlongTheTubeWithoutPenetrating) {
  const HapticScene scene = loadHapticScene(scenePath("alpha-puzzle-small.json"));
  HapticSessionSettings settings;
  settings.method = HapticMethod::Constraint;
  settings.seconds = 2.9;  // the pull (0.3-1.0 s), the slide along +y (1.0-1.8 s) and back along -y (1.8-2.8 s)
  const HapticSessionResult result = runHapticSession(scene, settings);
  const HapticSessionSummary& s = result.summary;
  EXPECT_EQ(s.maxPenetrationCells, 0.0);
  EXPECT_EQ(s.failedCycles, 0);
  EXPECT_GT(s.maxContacts, 0);    // the pull brought the pieces into contact...
  EXPECT_LT(s.maxContacts, 100);  // ... with few contacts (the paper: under 10 in the peg)
  ASSERT_FALSE(result.ticks.empty());
  const double y0 = scene.worldFromBodyStart.translation().y();
  double mostPositive = 0.0;
  int ticksInContact = 0;
  for (const HapticTickRecord& t : result.ticks) {
    EXPECT_EQ(t.penetration, 0.0);
    if (t.time < 1.0) continue;
    // Held back by the static loop: the god-object stays behind the device along -x (pulled to -0.038 m)...
    EXPECT_GT(t.worldFromSimulation.translation().x() - t.worldFromDevice.translation().x(), 0.0005) << t.time;
    ticksInContact += t.contacts > 0;
    mostPositive = std::max(mostPositive, t.worldFromSimulation.translation().y() - y0);
  }
  // ... in contact nearly all the time while it slides along the tube with the user, both ways (a point held at
  // the slide floor must not freeze it: the depth correction lifts it).
  EXPECT_GT(ticksInContact, 0.95 * 1900);
  EXPECT_GT(mostPositive, 0.003);
  EXPECT_LT(result.ticks.back().worldFromSimulation.translation().y() - y0, -0.003);
}

TEST(AlphaPuzzleScene, FieldIsCachedAndReloadedIdentically) {
  // One folder per process: test runs of several builds may share the machine.
  const std::filesystem::path cache =
      std::filesystem::temp_directory_path() / ("sdfccd_alpha_cache_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(cache);
  HapticSceneLoadSettings load;
  load.cacheDir = cache.string();
  const HapticScene built = loadHapticScene(scenePath("alpha-puzzle-small.json"), load);
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(cache)) {
    EXPECT_EQ(entry.path().extension(), ".sdf");
    ++files;
  }
  EXPECT_EQ(files, 1);
  const HapticScene cached = loadHapticScene(scenePath("alpha-puzzle-small.json"), load);
  EXPECT_EQ(built.grid->grid().values(), cached.grid->grid().values());
  EXPECT_EQ(built.cellSize, cached.cellSize);
  // A damaged entry is rebuilt.
  for (const auto& entry : std::filesystem::directory_iterator(cache)) std::filesystem::resize_file(entry.path(), 10);
  const HapticScene rebuilt = loadHapticScene(scenePath("alpha-puzzle-small.json"), load);
  EXPECT_EQ(built.grid->grid().values(), rebuilt.grid->grid().values());
  std::filesystem::remove_all(cache);
}

TEST(AlphaPuzzleScene, BadProceduralKeysGiveOneLineErrors) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("sdfccd_alpha_bad_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto expectError = [&](const std::string& json, const std::string& key) {
    const std::string file = (dir / "scene.json").string();
    {
      std::ofstream out(file);
      out << json;
    }
    try {
      loadHapticScene(file);
      ADD_FAILURE() << "no error for " << json;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_NE(what.find(key), std::string::npos) << what;
    }
  };
  const std::string shell = R"("shell": {"shape": "box", "halfExtents": [0.01, 0.01, 0.01]})";
  const std::string rest = R"("start": {"position": [0, 0.1, 0]}, "script": [{"t": 0, "position": [0, 0.1, 0]}])";
  expectError(R"({"obstacle": {"mesh": {"procedural": "teapot"}}, )" + shell + ", " + rest + "}", "procedural");
  expectError(R"({"obstacle": {"mesh": {"procedural": 3}}, )" + shell + ", " + rest + "}", "procedural");
  expectError(
      R"({"obstacle": {"mesh": {"procedural": "alpha-puzzle-piece", "scale": -1}}, )" + shell + ", " + rest + "}",
      "scale");
  const std::string plane = R"("obstacle": {"plane": {"normal": [0, 1, 0]}})";
  expectError("{" + plane + R"(, "shell": {"shape": "alpha-puzzle-piece", "scale": 0}, )" + rest + "}", "scale");
  expectError("{" + plane + ", " + shell + R"(, "poseFrame": "world", )" + rest + "}", "poseFrame");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sdfccd::haptics
