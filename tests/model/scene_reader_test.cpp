/// @file
/// @brief The scene reader (sdfccd/model/scene.h) without Bullet: strict validation with one-line errors naming
/// the scene and the key, the camera and the file lookup, and the shipped scene files parse.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "sdfccd/error.h"
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
