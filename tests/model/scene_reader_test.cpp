/// @file
/// @brief The scene reader (sdfccd/model/scene.h) without Bullet: strict validation with one-line errors naming
/// the scene and the key, the camera and the file lookup, and the shipped scene files parse.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/model/runaway_guard.h"
#include "sdfccd/model/scene.h"

namespace sdfccd {
namespace {

Scene sceneFromText(const std::string& text, const SceneLoadSettings& settings = {}) {
  return parseScene(text, "test", SDFCCD_ASSETS_DIR, settings);
}

std::string errorOf(const std::string& text) {
  try {
    sceneFromText(text);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const char* kBody = R"({ "primitive": { "type": "box", "half_extents": [0.1, 0.1, 0.1] }, "mass": 1.0 })";

std::string withBody(const std::string& top, const std::string& body = kBody) {
  return "{ " + top + (top.empty() ? "" : ", ") + "\"bodies\": [" + body + "] }";
}

TEST(SceneReader, BadScenesFailWithOneLineNamingTheKey) {
  const std::string cases[][2] = {
      {withBody("\"timestep\": 0.001, \"colour\": 3"), "colour"},
      {withBody("", R"({ "primitive": { "type": "box" }, "mass": -1.0 })"), "bodies[0].mass"},
      {withBody("", R"({ "primitive": { "type": "box" }, "mass": 0.0 })"), "mass"},
      {withBody("", R"({ "primitive": { "type": "box" } })"), "mass"},
      {withBody("", R"({ "mesh": "meshes/no-such-mesh.off", "mass": 1.0 })"), "missing file"},
      {withBody("", R"({ "primitive": { "type": "box" }, "mass": 1.0, "orientation": [1, 0.1, 0, 0] })"),
       "unit quaternion"},
      {withBody("", R"({ "primitive": { "type": "box" }, "mass": 1.0, "position": [0, 1e999, 0] })"), "JSON"},
      {withBody("", R"({ "primitive": { "type": "box" }, "mass": 1.0, "spin": 2 })"), "spin"},
      {withBody("", R"({ "primitive": { "type": "cone" }, "mass": 1.0 })"), "bodies[0].primitive.type"},
      {withBody("\"effects\": [\"gravity\", \"magnetism\"]"), "magnetism"},
      {withBody("\"timestep\": -0.01"), "timestep"},
      {withBody("\"contact\": { \"model\": \"implicit\" }"), "contact.model"},
      {withBody("\"contact\": { \"force_timing\": \"later\" }"), "contact.force_timing"},
      {withBody("\"camera\": { \"eye\": [0, 1, 2], \"target\": [0, 0, 0], \"fov\": 190 }"), "camera.fov"},
      {withBody("\"camera\": { \"eye\": [0, 1, 2] }"), "camera"},
      {"{ \"bodies\": [] }", "bodies"},
      {"{ \"timestep\": 0.001, ", "JSON"},
      {"{ \"timestep\": NaN, \"bodies\": [] }", "JSON"},
      {"[1, 2]", "JSON object"},
  };
  for (const auto& c : cases) {
    const std::string message = errorOf(c[0]);
    EXPECT_NE(message.find(c[1]), std::string::npos) << "scene: " << c[0] << "\nmessage: " << message;
    EXPECT_NE(message.find("scene 'test'"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_EQ(errorOf(withBody("\"effects\": [\"gravity\"]")), "");
}

TEST(SceneReader, ReadsContactCameraAndEffects) {
  const Scene s = sceneFromText(withBody(R"("effects": ["ground", "gravity"], "ground": { "height": -0.5 },
      "contact": { "mode": "penalty", "model": "discrete", "force_timing": "next_step", "direction": "field_gradient" },
      "camera": { "eye": [0, 1, 2], "target": [0, 0, 0] })"));
  EXPECT_EQ(s.effectList(), "gravity,ground");
  EXPECT_EQ(s.groundHeight, -0.5);
  EXPECT_EQ(s.contact.model, PenaltyModel::Discrete);
  EXPECT_EQ(s.contact.forceTiming, ForceTiming::NextStep);
  EXPECT_EQ(s.contact.direction, PenaltyDirection::FieldGradient);
  EXPECT_EQ(s.contact.solver, ContactSolver::Mlcp);  // the default (used in solver mode only)
  EXPECT_EQ(sceneFromText(withBody(R"("contact": { "solver": "sequential_impulse" })")).contact.solver,
            ContactSolver::SequentialImpulse);
  EXPECT_EQ(sceneFromText(withBody(R"("contact": { "mode": "solver", "solver": "nncg" })")).contact.solver,
            ContactSolver::Nncg);
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_EQ(s.camera->eye, Vec3(0, 1, 2));
  EXPECT_EQ(s.camera->fovDegrees, 40.0);  // the renderer's default
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(s.bodies[0].name, "body0");
  ASSERT_TRUE(s.bodies[0].primitive.has_value());
  EXPECT_EQ(s.bodies[0].primitive->halfExtents, Vec3::Constant(0.1));
}

// Files are looked for in the current folder, then the scene's folder and its ancestors, then the extra search
// folders; without requireFiles an unfound file keeps the path as written.
TEST(SceneReader, FilesAreFoundThroughTheSceneFolderOrSearchFolders) {
  const std::string scenes = std::string(SDFCCD_ASSETS_DIR) + "/scenes";
  const std::string body = R"({ "mesh": "meshes/bunny.off", "mass": 1.0 })";
  const Scene s = parseScene(withBody("", body), "test", scenes);
  EXPECT_TRUE(std::filesystem::is_regular_file(s.bodies[0].mesh)) << s.bodies[0].mesh;

  const std::filesystem::path elsewhere =
      std::filesystem::temp_directory_path() / ("sdfccd_scene_search_" + std::to_string(::getpid()));
  EXPECT_THROW(parseScene(withBody("", body), "test", elsewhere.string()), Error);
  SceneLoadSettings search;
  search.searchFolders = {SDFCCD_ASSETS_DIR};
  EXPECT_TRUE(
      std::filesystem::is_regular_file(parseScene(withBody("", body), "t", elsewhere.string(), search).bodies[0].mesh));
  SceneLoadSettings lenient;
  lenient.requireFiles = false;
  const std::string missing = R"({ "mesh": "no/such/mesh.off", "mass": 1.0 })";
  EXPECT_EQ(parseScene(withBody("", missing), "t", elsewhere.string(), lenient).bodies[0].mesh, "no/such/mesh.off");
}

TEST(SceneReader, LoadSceneNamesTheFileInErrorsAndNamesTheScene) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("sdfccd_scene_reader_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "my-scene.json").string();
  {
    std::ofstream out(file);
    out << withBody("");
  }
  EXPECT_EQ(loadScene(file).name, "my-scene");
  EXPECT_EQ(loadScene(file).path, file);
  {
    std::ofstream out(file);
    out << withBody("\"frames\": 0");
  }
  try {
    loadScene(file);
    ADD_FAILURE() << "frames 0 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scene '" + file + "': frames"), std::string::npos) << e.what();
  }
  EXPECT_THROW(loadScene((dir / "none.json").string()), Error);
  std::filesystem::remove_all(dir);
}

// Absurd magnitudes and bad contact settings: every number is range-checked before use (integers before any cast),
// each defect one line naming the key.
TEST(SceneReader, AbsurdAndConflictingSettingsFailNamingTheKey) {
  const std::string box = R"("primitive": { "type": "box", "half_extents": [0.1, 0.1, 0.1] })";
  auto body = [&](const std::string& extra) { return "{ " + box + ", \"mass\": 1.0" + extra + " }"; };
  auto contact = [&](const std::string& keys) { return withBody("\"contact\": { " + keys + " }"); };
  const std::string cases[][2] = {
      // Integers: JSON integers in range, never a cast of 1e300 or of 2^64.
      {withBody("\"frames\": 1e300"), "frames must be an integer"},
      {withBody("\"frames\": 18446744073709551615"), "frames must be in 1..100000000"},
      {withBody("\"frames\": 9223372036854775808"), "frames must be in"},
      {withBody("\"frames\": -5"), "frames must be in"},
      {withBody("", body(", \"resolution\": 1e300")), "bodies[0].resolution must be an integer"},
      {withBody("", body(", \"resolution\": 1000000000000")), "bodies[0].resolution must be in"},
      {withBody("", body(", \"points\": 1.5")), "bodies[0].points must be an integer"},
      {contact("\"subintervals\": 1e12"), "contact.subintervals"},
      // Contact settings: negative, conflicting, outside [0, 2].
      {contact("\"stiffness\": -1"), "contact.stiffness must be in (0, 1e+09]"},
      {contact("\"stiffness\": 0"), "contact.stiffness"},
      {contact("\"damping\": -0.5"), "contact.damping must be in [0, 1e+06]"},
      {contact("\"stiffness_per_area\": -1"), "contact.stiffness_per_area"},
      {contact("\"stiffness_per_area\": 0"), "contact.stiffness_per_area"},
      {contact("\"damping_ratio\": 2.5"), "contact.damping_ratio must be in [0, 2]"},
      {contact("\"damping_ratio\": -0.1"), "contact.damping_ratio"},
      {contact("\"stiffness\": 2000, \"stiffness_per_area\": 1e7"), "contact.stiffness and contact.stiffness_per_area"},
      {contact("\"damping\": 5, \"damping_ratio\": 1"), "contact.damping and contact.damping_ratio"},
      {contact("\"model\": \"discrete\", \"mode\": \"solver\""), "contact.model discrete applies to penalty mode"},
      {contact("\"mode\": \"implicit\""), "contact.mode"},
      {contact("\"solver\": \"dantzig\""), "contact.solver must be mlcp, sequential_impulse or nncg"},
      {contact("\"mode\": \"penalty\", \"solver\": \"mlcp\""), "contact.solver applies to solver mode only"},
      {contact("\"toi_depth_cells\": -1"), "contact.toi_depth_cells"},
      {contact("\"toi_depth_cells\": 1e6"), "contact.toi_depth_cells"},
      // Absurd magnitudes (values that blow a run up, and their neighbours).
      {contact("\"stiffness\": 1e12"), "contact.stiffness must be in (0, 1e+09] (got 1e+12)"},
      {contact("\"damping\": 1e12"), "contact.damping"},
      {contact("\"friction\": 1e12"), "contact.friction must be in [0, 10]"},
      {contact("\"friction\": -0.1"), "contact.friction"},
      {contact("\"stiffness_per_area\": 1e20"), "contact.stiffness_per_area"},
      {withBody("", "{ " + box + ", \"mass\": 1e-30 }"), "bodies[0].mass must be in [1e-06, 1e+06]"},
      {withBody("", "{ " + box + ", \"mass\": 1e30 }"), "bodies[0].mass"},
      {withBody("", body(", \"friction\": 1e12")), "bodies[0].friction"},
      {withBody("", body(", \"restitution\": 1.5")), "bodies[0].restitution must be in [0, 1]"},
      {withBody("", body(", \"restitution\": -1")), "bodies[0].restitution"},
      {withBody("", body(", \"scale\": 1e-30")), "bodies[0].scale"},
      {withBody("", body(", \"scale\": -2")), "bodies[0].scale"},
      {withBody("", body(", \"position\": [0, 1e300, 0]")), "bodies[0].position"},
      {withBody("", body(", \"velocity\": [1e5, 0, 0]")), "bodies[0].velocity must be at most"},
      {withBody("", body(", \"angular_velocity\": [0, 0, 1e9]")), "bodies[0].angular_velocity"},
      {withBody("", R"({ "primitive": { "type": "sphere", "radius": 1e300 }, "mass": 1.0 })"),
       "bodies[0].primitive.radius"},
      {withBody("", R"({ "primitive": { "type": "box", "half_extents": [1e-30, 1, 1] }, "mass": 1.0 })"),
       "bodies[0].primitive.half_extents"},
      {withBody("\"timestep\": 1e-300"), "timestep must be in [1e-07, 1]"},
      {withBody("\"timestep\": 5"), "timestep"},
      {withBody("\"gravity\": [0, -1e300, 0]"), "gravity"},
      {withBody("\"ground\": { \"height\": 1e300 }"), "ground.height"},
      // The runaway guard's own keys.
      {withBody("\"guard\": { \"energy_factor\": 0.5 }"), "guard.energy_factor must be >= 1"},
      {withBody("\"guard\": { \"max_speed\": -1 }"), "guard.max_speed"},
      {withBody("\"guard\": { \"action\": \"ignore\" }"), "guard.action must be stop, report or off"},
      {withBody("\"guard\": { \"energy\": 2 }"), "guard.energy is not a known key"},
      {withBody("\"guard\": 3"), "guard must be a JSON object"},
  };
  for (const auto& c : cases) {
    const std::string message = errorOf(c[0]);
    EXPECT_NE(message.find(c[1]), std::string::npos) << "scene: " << c[0] << "\nmessage: " << message;
    EXPECT_NE(message.find("scene 'test'"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  // The bounds themselves are accepted (the ranges are closed where the table says so).
  EXPECT_EQ(errorOf(contact("\"stiffness\": 1e9, \"damping\": 1e6, \"friction\": 10")), "");
  EXPECT_EQ(errorOf(withBody("\"timestep\": 1e-7", body(", \"restitution\": 1, \"friction\": 0"))), "");
  EXPECT_EQ(errorOf(withBody("", "{ " + box + ", \"mass\": 1e-6 }")), "");
  EXPECT_EQ(errorOf(withBody("", "{ " + box + ", \"mass\": 1e6 }")), "");
  // A static body's mass is ignored, so it is not range-checked.
  EXPECT_EQ(errorOf(withBody("", "{ " + box + ", \"static\": true, \"mass\": 1e30 }")), "");
}

TEST(SceneReader, ReadsTheGuard) {
  const Scene defaults = sceneFromText(withBody(""));
  EXPECT_EQ(defaults.guard.action, GuardAction::Stop);
  EXPECT_EQ(defaults.guard.energyFactor, 1000.0);
  const Scene s = sceneFromText(
      withBody(R"("guard": { "energy_factor": 50, "max_speed": 20, "extent_factor": 3, "action": "report" })"));
  EXPECT_EQ(s.guard.action, GuardAction::Report);
  EXPECT_EQ(s.guard.energyFactor, 50.0);
  EXPECT_EQ(s.guard.maxSpeed, 20.0);
  EXPECT_EQ(s.guard.extentFactor, 3.0);
  EXPECT_EQ(sceneFromText(withBody(R"("guard": { "action": "off" })")).guard.action, GuardAction::Off);
}

// The runaway guard against analytic motions: free fall (the energy gravity supplies is allowed, exactly),
// a resting box that explodes, a body too fast or too far, kinematic bodies' share, and "off".
TEST(RunawayGuard, AllowsWhatPhysicsAllowsAndNamesTheBodyOtherwise) {
  const double g = 9.81;
  const Scene falling = sceneFromText(
      withBody(R"("effects": ["gravity"])", R"({ "name": "rock", "primitive": { "type": "box" }, "mass": 2.0 })"));
  const RunawayGuard fallGuard(falling, 0.0);
  for (double t : {0.5, 10.0, 100.0}) {
    // Free fall: v = g t, y = -g t^2 / 2, KE = m g^2 t^2 / 2 = the work gravity did.
    const std::vector<GuardBodyState> state = {{Vec3(0, -0.5 * g * t * t, 0), Vec3(0, -g * t, 0)}};
    EXPECT_FALSE(fallGuard.check(t, state, 0.5 * 2.0 * g * g * t * t)) << t;
  }
  // Without the gravity budget (no "gravity" effect) the same motion at t = 100 s is a runaway.
  const Scene floating =
      sceneFromText(withBody("", R"({ "name": "rock", "primitive": { "type": "box" }, "mass": 2.0 })"));
  const RunawayGuard floatGuard(floating, 0.0);
  const std::optional<std::string> fast = floatGuard.check(100.0, {{Vec3(0, -1, 0), Vec3(0, -981, 0)}}, 9.6e5);
  ASSERT_TRUE(fast);
  EXPECT_NE(fast->find("body 'rock' (bodies[0])"), std::string::npos) << *fast;
  // Budget of a body at rest without gravity: 1000 * 1/2 m (1 m/s)^2 = 1000 J for 2 kg.
  EXPECT_DOUBLE_EQ(floatGuard.energyBound({{Vec3::Zero(), Vec3::Zero()}}), 1000.0);
  EXPECT_FALSE(floatGuard.check(1.0, {{Vec3::Zero(), Vec3(30, 0, 0)}}, 900.0));
  const std::optional<std::string> hot = floatGuard.check(1.0, {{Vec3::Zero(), Vec3(40, 0, 0)}}, 1600.0);
  ASSERT_TRUE(hot);
  EXPECT_NE(hot->find("kinetic energy 1600 J"), std::string::npos) << *hot;
  EXPECT_NE(hot->find("body 'rock'"), std::string::npos) << *hot;
  // Too far: the extent is at least 0.1 m, so 1000 * 0.1 m = 100 m at rest.
  EXPECT_DOUBLE_EQ(floatGuard.distanceBound(0.0), 100.0);
  const std::optional<std::string> far = floatGuard.check(0.0, {{Vec3(0, 0, 150), Vec3::Zero()}}, 0.0);
  ASSERT_TRUE(far);
  EXPECT_NE(far->find("150 m from the origin"), std::string::npos) << *far;
  EXPECT_TRUE(floatGuard.check(0.0, {{Vec3(NAN, 0, 0), Vec3::Zero()}}, 0.0));

  // A resting box on the ground: potential above the lowest point is m g h.
  const Scene resting = sceneFromText(
      withBody(R"("effects": ["gravity", "ground"])",
               R"({ "name": "box", "primitive": { "type": "box" }, "mass": 1.0, "position": [0, 0.05, 0] })"));
  const RunawayGuard restGuard(resting, 0.0);
  EXPECT_NEAR(restGuard.energyBound({{Vec3(0, 0.05, 0), Vec3::Zero()}}), 1000.0 * (g * 0.05 + 0.5), 1e-9);
  const std::optional<std::string> boom = restGuard.check(0.3, {{Vec3(0, 0.05, 0), Vec3(0, 1e5, 0)}}, 5e9);
  ASSERT_TRUE(boom);
  EXPECT_NE(boom->find("body 'box'"), std::string::npos) << *boom;

  // A kinematic body at 5 m/s may throw a body at up to 10 m/s: the budget grows by 1/2 m (2V)^2 per body.
  const Scene pushed = sceneFromText(withBody("", R"({ "name": "ball", "primitive": { "type": "box" }, "mass": 1.0 },
             { "name": "bat", "primitive": { "type": "box" }, "kinematic": true, "velocity": [5, 0, 0] })"));
  const RunawayGuard pushGuard(pushed, 0.0);
  EXPECT_DOUBLE_EQ(pushGuard.energyBound({{Vec3::Zero(), Vec3::Zero()}, {Vec3::Zero(), Vec3::Zero()}}),
                   1000.0 * (0.5 * 100.0 + 0.5));
  EXPECT_DOUBLE_EQ(pushGuard.speedBound(0.0), 1010.0);

  Scene off = resting;
  off.guard.action = GuardAction::Off;
  EXPECT_FALSE(RunawayGuard(off, 0.0).check(0.3, {{Vec3(0, 0.05, 0), Vec3(0, 1e5, 0)}}, 5e9));
}

// Scene names are data: the default run folder's name never leaves its parent, never holds a separator, a newline or a
// control character, and is never ".", ".." or hidden.
TEST(SceneFolderName, KeepsSafeNamesAndNeutralizesPathsAndControlCharacters) {
  EXPECT_EQ(sceneFolderName("drop-bunnies_2.v1"), "drop-bunnies_2.v1");
  EXPECT_EQ(sceneFolderName("../../../x"), "_._.._.._x");
  EXPECT_EQ(sceneFolderName(".."), "_.");
  EXPECT_EQ(sceneFolderName("."), "_");
  EXPECT_EQ(sceneFolderName(".hidden"), "_hidden");
  EXPECT_EQ(sceneFolderName("/etc/passwd"), "_etc_passwd");
  EXPECT_EQ(sceneFolderName("a\nb"), "a_b");
  EXPECT_EQ(sceneFolderName(std::string("a\0b", 3)), "a_b");
  EXPECT_EQ(sceneFolderName("a\\b c\x1b\x7f"), "a_b_c__");
  EXPECT_EQ(sceneFolderName("\xc3\xbc"), "__");  // UTF-8 bytes are replaced one by one
  EXPECT_EQ(sceneFolderName(""), "scene");
  EXPECT_EQ(sceneFolderName(std::string(300, 'n')), std::string(64, 'n'));
  // Every byte value alone: the result is one safe byte.
  for (int c = 0; c < 256; ++c) {
    const std::string folder = sceneFolderName(std::string(1, static_cast<char>(c)));
    ASSERT_EQ(folder.size(), 1u) << c;
    const char f = folder[0];
    EXPECT_TRUE(std::isalnum(static_cast<unsigned char>(f)) || f == '_' || f == '-') << c;
  }
}

TEST(SceneReader, ShippedScenesParse) {
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
