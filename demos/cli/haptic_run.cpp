/// @file
/// @brief isHapticRunFolder, readHapticTicks, readHapticRunFolder: haptic run folders for render and plot.
#include "cli/haptic_run.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/run_frame_renderer.h"
#include "sdfccd/error.h"
#include "sdfccd/haptics/haptic_scene.h"

namespace sdfccd::cli {
// Named (not anonymous): the tool is a unity build, and these helpers must not meet other files' names.
namespace haptic_run_detail {

/// Splits one CSV line at commas (ticks.csv has no quoted fields).
std::vector<std::string> splitCsvLine(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

/// `text` as a finite double, or an Error naming `where` and `column`.
double parseFinite(const std::string& text, const std::string& where, const std::string& column) {
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value)) {
    throw Error(where + ": column '" + column + "' is not a finite number: '" + text + "'");
  }
  return value;
}

/// The blocky surface of a grid's inside nodes (value <= 0): a cube around every inside node, with the faces
/// towards outside nodes kept. Nodes are taken every `stride` along each axis so the mesh stays small enough to
/// draw (about 100 nodes per axis); the shape is right to a stride of cells, enough to see where the tool is.
TriangleMesh insideNodeSurface(const SdfGrid& grid) {
  const Vec3i n = grid.nodeCounts();
  const int stride = std::max(1, (n.maxCoeff() + 99) / 100);
  const Vec3i m = (n.array() - 1) / stride + 1;  // sampled nodes per axis
  const auto inside = [&](int i, int j, int k) {
    if (i < 0 || j < 0 || k < 0 || i >= m.x() || j >= m.y() || k >= m.z()) return false;
    return grid.value(i * stride, j * stride, k * stride) <= 0.0f;
  };
  const double half = 0.5 * stride * grid.spacing();
  TriangleMesh mesh;
  // The six face directions; for each, two tangent axes ordered so (t1 x t2) = the outward normal.
  static const std::array<std::array<int, 3>, 6> kDirections = {
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};
  for (int k = 0; k < m.z(); ++k) {
    for (int j = 0; j < m.y(); ++j) {
      for (int i = 0; i < m.x(); ++i) {
        if (!inside(i, j, k)) continue;
        const Vec3 center = grid.origin() + grid.spacing() * stride * Vec3(i, j, k);
        for (const auto& d : kDirections) {
          if (inside(i + d[0], j + d[1], k + d[2])) continue;
          const Vec3 normal(d[0], d[1], d[2]);
          const Vec3 t1 = normal.cross(std::abs(normal.x()) > 0.5 ? Vec3::UnitY() : Vec3::UnitX());
          const Vec3 t2 = normal.cross(t1);  // t1 x t2 = normal (|normal| = 1, t1 orthogonal)
          const Vec3 c = center + half * normal;
          const int base = static_cast<int>(mesh.vertices.size());
          mesh.vertices.push_back(c + half * (-t1 - t2));
          mesh.vertices.push_back(c + half * (t1 - t2));
          mesh.vertices.push_back(c + half * (t1 + t2));
          mesh.vertices.push_back(c + half * (-t1 + t2));
          mesh.triangles.push_back({base, base + 1, base + 2});
          mesh.triangles.push_back({base, base + 2, base + 3});
        }
      }
    }
  }
  if (mesh.triangles.empty()) throw Error("the obstacle's field has no node inside it: nothing to draw");
  return mesh;
}

/// A square slab of side `side` lying on the plane (its top face on it), centred under `around`: a plane has
/// no size, so it is drawn as large as the tool's motion.
TriangleMesh planeSlab(const PlaneField& plane, const Vec3& around, double side) {
  const Vec3 n = plane.normal();
  const Vec3 t1 = n.cross(std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).normalized();
  const Vec3 t2 = n.cross(t1);
  const Vec3 center = around - (n.dot(around) - plane.offset()) * n;  // projected onto the plane
  const double h = 0.5 * side;
  const double thickness = 0.02 * side;
  TriangleMesh mesh;
  for (int corner = 0; corner < 8; ++corner) {
    const double a = (corner & 1) ? h : -h;
    const double b = (corner & 2) ? h : -h;
    const double c = (corner & 4) ? 0.0 : -thickness;
    mesh.vertices.push_back(center + a * t1 + b * t2 + c * n);
  }
  // The box's faces, counter-clockwise seen from outside (t1, t2, n right-handed).
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

/// A file cut at a line's end reads as a shorter run: summary.json's "haptic_ticks" (when the folder has one and
/// the session ended without an error, which may leave its last tick unrecorded) says how many rows there are.
void checkTickCount(const std::string& folder, const std::string& ticksPath, std::size_t rows) {
  std::ifstream in(std::filesystem::path(folder) / kRunSummaryFile);
  if (!in) return;  // plots need no summary
  const nlohmann::json summary = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!summary.is_object() || !summary.contains("haptic_ticks") || !summary["haptic_ticks"].is_number_integer()) {
    return;
  }
  if (summary.contains("error") && !summary["error"].is_null()) return;
  const auto expected = summary["haptic_ticks"].get<std::int64_t>();
  if (expected != static_cast<std::int64_t>(rows)) {
    throw Error(ticksPath + ": " + std::to_string(rows) + " ticks, summary.json's haptic_ticks is " +
                std::to_string(expected) + " (a truncated file?)");
  }
}

}  // namespace haptic_run_detail

bool isHapticRunFolder(const std::string& folder) {
  std::error_code error;
  return std::filesystem::is_regular_file(std::filesystem::path(folder) / kHapticTicksFile, error) &&
         !std::filesystem::exists(std::filesystem::path(folder) / kRunFramesFile, error);
}

RunFrames readHapticTicks(const std::string& folder) {
  const std::string path = (std::filesystem::path(folder) / kHapticTicksFile).string();
  std::ifstream in(path);
  if (!in) throw Error("cannot read the haptic run's ticks '" + path + "'");
  std::string line;
  if (!std::getline(in, line) || line.empty()) throw Error(path + ": empty file (no header)");
  const std::vector<std::string> header = haptic_run_detail::splitCsvLine(line);
  std::map<std::string, std::size_t> columnOf;
  for (std::size_t c = 0; c < header.size(); ++c) columnOf[header[c]] = c;
  static const char* const kNeeded[] = {"tick",     "time",     "sim_x",    "sim_y",    "sim_z",      "sim_qw",
                                        "sim_qx",   "sim_qy",   "sim_qz",   "force_x",  "force_y",    "force_z",
                                        "torque_x", "torque_y", "torque_z", "contacts", "penetration"};
  for (const char* name : kNeeded) {
    if (columnOf.count(name) == 0) throw Error(path + ": no column '" + std::string(name) + "'");
  }
  RunFrames frames;
  std::vector<double>& force = frames.series["force"];
  std::vector<double>& torque = frames.series["torque"];
  std::vector<double>& contacts = frames.series["contacts"];
  std::vector<double>& penetration = frames.series["penetration"];
  int lineNumber = 1;
  while (std::getline(in, line)) {
    ++lineNumber;
    const std::string where = path + ":" + std::to_string(lineNumber);
    const std::vector<std::string> fields = haptic_run_detail::splitCsvLine(line);
    if (fields.size() != header.size()) {
      throw Error(where + ": " + std::to_string(fields.size()) + " values, the header has " +
                  std::to_string(header.size()) + " (a truncated file?)");
    }
    const auto value = [&](const char* name) {
      return haptic_run_detail::parseFinite(fields[columnOf.at(name)], where, name);
    };
    frames.frameNumbers.push_back(static_cast<int>(value("tick")));
    frames.times.push_back(value("time"));
    const Quat q(value("sim_qw"), value("sim_qx"), value("sim_qy"), value("sim_qz"));
    if (q.norm() < 0.5) throw Error(where + ": the pose's quaternion sim_q* is not a rotation");
    frames.worldFromBody.push_back({bodyPose(Vec3(value("sim_x"), value("sim_y"), value("sim_z")), q)});
    force.push_back(Vec3(value("force_x"), value("force_y"), value("force_z")).norm());
    torque.push_back(Vec3(value("torque_x"), value("torque_y"), value("torque_z")).norm());
    contacts.push_back(value("contacts"));
    penetration.push_back(value("penetration"));
  }
  if (frames.times.empty()) throw Error(path + ": no ticks after the header");
  haptic_run_detail::checkTickCount(folder, path, frames.times.size());
  frames.seriesSource = {
      {"force", "force_*"}, {"torque", "torque_*"}, {"contacts", "contacts"}, {"penetration", "penetration_m"}};
  return frames;
}

std::string hapticRunSceneFile(const std::string& folder) {
  const std::string path = (std::filesystem::path(folder) / kRunSummaryFile).string();
  std::ifstream in(path);
  if (!in) throw Error("cannot read the haptic run's summary '" + path + "'");
  nlohmann::json summary;
  try {
    summary = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw Error(path + ": not JSON: " + e.what());
  }
  if (!summary.is_object() || !summary.contains("scene_file") || !summary["scene_file"].is_string()) {
    throw Error(path + ": no \"scene_file\" (the haptic scene to draw; written by sdfccd haptics --out)");
  }
  return summary["scene_file"].get<std::string>();
}

RunFolder readHapticRunFolder(const std::string& folder, const std::string& cacheDir) {
  RunFolder run;
  run.folder = folder;
  run.frames = readHapticTicks(folder);
  const std::string sceneFile = hapticRunSceneFile(folder);
  haptics::HapticSceneLoadSettings load;
  load.cacheDir = cacheDir;
  const haptics::HapticScene scene = haptics::loadHapticScene(sceneFile, load);
  run.scene.path = sceneFile;

  RunBody tool;
  tool.name = "tool";
  tool.mesh = scene.shellMesh;  // body frame: centred on the centre of mass, as the recorded poses are
  if (!tool.mesh) throw Error(sceneFile + ": the scene keeps no mesh of its tool");
  if (!scene.obstacles.empty()) {  // several obstacles (haptic_obstacles.h): each at its path's pose per frame
    run.scene.bodies = {tool};
    for (const haptics::HapticObstacle& o : scene.obstacles) {
      RunBody body;
      body.name = o.name.empty() ? "obstacle " + std::to_string(run.scene.bodies.size()) : o.name;
      body.isStatic = !o.path.moving();
      body.mass = 0.0;
      body.worldFromBody = o.path.poseAt(0.0);
      if (o.mesh) {
        body.mesh = o.mesh;
      } else if (o.grid) {
        body.mesh = std::make_shared<const TriangleMesh>(haptic_run_detail::insideNodeSurface(o.grid->grid()));
      } else if (o.plane) {
        Box3 reach;  // as below: the tool's whole motion plus twice its size
        const Box3 toolBox = tool.mesh->bounds();
        for (const std::vector<Rigid>& poses : run.frames.worldFromBody)
          for (int corner = 0; corner < 8; ++corner)
            reach.extend(poses[0] * toolBox.corner(static_cast<Box3::CornerType>(corner)));
        const double side = reach.sizes().maxCoeff() + 2.0 * toolBox.sizes().maxCoeff();
        body.mesh = std::make_shared<const TriangleMesh>(
            haptic_run_detail::planeSlab(*o.plane, body.worldFromBody.inverse() * reach.center(), side));
      }
      run.scene.bodies.push_back(body);
    }
    for (std::size_t f = 0; f < run.frames.times.size(); ++f)
      for (const haptics::HapticObstacle& o : scene.obstacles)
        run.frames.worldFromBody[f].push_back(o.path.poseAt(run.frames.times[f]));
    return run;
  }
  RunBody obstacle;
  obstacle.name = "obstacle";
  obstacle.isStatic = true;
  obstacle.mass = 0.0;
  if (scene.grid) {
    obstacle.mesh = std::make_shared<const TriangleMesh>(haptic_run_detail::insideNodeSurface(scene.grid->grid()));
  } else if (scene.plane) {
    // As large as the tool's whole motion plus twice the tool's size.
    Box3 reach;
    const Box3 toolBox = tool.mesh->bounds();
    for (const std::vector<Rigid>& poses : run.frames.worldFromBody) {
      for (int corner = 0; corner < 8; ++corner) {
        reach.extend(poses[0] * toolBox.corner(static_cast<Box3::CornerType>(corner)));
      }
    }
    const double side = reach.sizes().maxCoeff() + 2.0 * toolBox.sizes().maxCoeff();
    obstacle.mesh = std::make_shared<const TriangleMesh>(
        haptic_run_detail::planeSlab(*scene.plane, scene.worldFromSdf.inverse() * reach.center(), side));
  } else {
    throw Error(sceneFile + ": the scene has no obstacle to draw");
  }
  obstacle.worldFromBody = scene.worldFromSdf;
  run.scene.bodies = {tool, obstacle};
  for (std::vector<Rigid>& poses : run.frames.worldFromBody) poses.push_back(scene.worldFromSdf);
  return run;
}

}  // namespace sdfccd::cli
