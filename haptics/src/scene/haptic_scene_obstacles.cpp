/// @file
/// @brief The "obstacles" list of a haptic scene and the tool's own field ("shell.field"); see
/// docs/scene-format.md.
#include <algorithm>
#include <string>

#include "scene/haptic_scene_reader.h"
#include "sdfccd/error.h"
#include "sdfccd/haptics/procedural_shapes.h"
#include "sdfccd/shell/point_shell.h"

namespace sdfccd::haptics {

namespace {

/// A shell obstacle: its mesh (in the obstacle's frame, not centred) and the points sampled from it.
void readObstacleShell(const Reader& r, const Json& j, const std::string& where, HapticObstacle& o) {
  r.checkKeys(j,
              {"shape", "halfExtents", "radius", "height", "segments", "subdivisions", "path", "size", "scale",
               "holeRadius", "points", "iterations"},
              where);
  TriangleMesh mesh = readShellMesh(r, j, where);
  ShellSamplingSettings sampling;
  sampling.points = r.integer(j, "points", where, 1000, 1, 10000000);
  sampling.iterations = r.integer(j, "iterations", where, 10, 0, 1000);
  sampling.threads = 1;
  o.shell = std::make_shared<const PointTree>(sampleShell(mesh, sampling));
  o.mesh = std::make_shared<const TriangleMesh>(std::move(mesh));
  // A nominal cell for the tolerances: the points' mean spacing.
  o.cellSize = std::sqrt(o.mesh->area() / sampling.points);
}

/// "path": keyframes of the obstacle's pose ({"t", "position", "rotationVector"}), as the user script's.
UserScript readPath(const Reader& r, const Json& j, const std::string& at) {
  if (!j.at("path").is_array() || j.at("path").empty()) r.fail(at, "must be a non-empty array of keyframes");
  std::vector<PoseKeyframe> keys;
  for (const Json& k : j.at("path")) {
    const std::string where = at + "[" + std::to_string(keys.size()) + "]";
    r.checkObject(k, where);
    r.checkKeys(k, {"t", "position", "rotationVector"}, where);
    (void)r.number(k, "t", where, 0.0, /*required=*/true);
    keys.push_back({r.ranged(k, "t", where, 0.0, 0.0, 3600.0), readPose(r, k, where)});
  }
  try {
    return UserScript(std::move(keys));
  } catch (const Error& e) {  // increasing times, finite poses: with the key named
    r.fail(at, std::string("is invalid: ") + e.what());
  }
  return {};
}

}  // namespace

void readObstacles(const Reader& r, const Json& root, const std::string& cacheDir, HapticScene& scene) {
  if (!root.at("obstacles").is_array() || root.at("obstacles").empty())
    r.fail("obstacles", "must be a non-empty array");
  double finest = scene.toolField ? scene.toolField->grid().spacing() : 0.0;
  for (const Json& j : root.at("obstacles")) {
    const std::string at = "obstacles[" + std::to_string(scene.obstacles.size()) + "]";
    r.checkObject(j, at);
    HapticObstacle o;
    if (j.contains("shell")) {
      r.checkKeys(j, {"name", "shell", "pose", "path"}, at);
      readObstacleShell(r, r.object(j, "shell", at), Reader::join(at, "shell"), o);
      if (!scene.toolField) r.fail(Reader::join(at, "shell"), "needs the tool's field (\"shell.field\")");
    } else {
      SceneField field = readSceneField(r, j, at, cacheDir, {"name", "pose", "path"});
      o.grid = std::move(field.grid);
      o.plane = field.plane;
      o.cellSize = field.cellSize;
      finest = finest > 0.0 ? std::min(finest, o.cellSize) : o.cellSize;
    }
    o.name = j.contains("name") ? r.string(j, "name", at) : "";
    if (j.contains("pose") && j.contains("path")) r.fail(Reader::join(at, "path"), "give either \"pose\" or \"path\"");
    if (j.contains("pose")) {
      const std::string where = Reader::join(at, "pose");
      const Json& pose = r.object(j, "pose", at);
      r.checkKeys(pose, {"position", "rotationVector"}, where);
      o.path.worldFromObstacle = readPose(r, pose, where);
    }
    if (j.contains("path")) o.path.keys = readPath(r, j, Reader::join(at, "path"));
    scene.obstacles.push_back(std::move(o));
  }
  if (!(finest > 0.0)) r.fail("obstacles", "needs a field obstacle or the tool's field (for the tolerances' cell)");
  scene.cellSize = finest;
}

std::shared_ptr<const GridField> readToolField(const Reader& r, const Json& shellJson, const std::string& at,
                                               const TriangleMesh& centredMesh, const std::string& cacheDir) {
  const std::string where = Reader::join(at, "field");
  const Json& f = r.object(shellJson, "field", at);
  r.checkKeys(f, {"resolution", "padding", "offsetCells"}, where);
  SdfBuildSettings build;
  build.resolution = r.integer(f, "resolution", where, 64, 4, 2048);
  build.padding = r.integer(f, "padding", where, 4, 0, 64);
  build.threads = 0;
  std::shared_ptr<const SdfGrid> grid = meshObstacleGrid(centredMesh, build, cacheDir, "tool");
  const double offsetCells = r.number(f, "offsetCells", where, 0.0);
  if (offsetCells != 0.0) {  // grows (> 0) or shrinks the tool's field by a fraction of its cell
    std::vector<float> values = grid->values();
    for (float& v : values) v = static_cast<float>(v - offsetCells * grid->spacing());
    grid = std::make_shared<const SdfGrid>(grid->nodeCounts(), grid->origin(), grid->spacing(), std::move(values));
  }
  return std::make_shared<const GridField>(grid);
}

TriangleMesh blockWithHoleMesh(const Reader& r, const Json& j, const std::string& where) {
  const Vec3 half = r.vec3(j, "halfExtents", where, Vec3::Zero(), true);
  if (!(half.minCoeff() > 0.0)) r.fail(Reader::join(where, "halfExtents"), "must be > 0");
  const double radius = r.positive(j, "holeRadius", where, 0.0, true);
  if (!(radius < std::min(half.x(), half.z())))
    r.fail(Reader::join(where, "holeRadius"), "must be smaller than halfExtents x and z");
  return blockWithHole(half, radius, r.integer(j, "segments", where, 96, 3, 4096));
}

}  // namespace sdfccd::haptics
