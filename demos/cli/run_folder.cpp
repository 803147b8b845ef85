/// @file
/// @brief RunFolder: scene.json and frames.csv of a saved run, read by column name.
#include "cli/run_folder.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sdfccd/error.h"
#include "sdfccd/io/mesh_loader.h"

namespace sdfccd::cli {

namespace fs = std::filesystem;

namespace {

std::string lowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string trim(const std::string& text) {
  std::size_t begin = 0;
  std::size_t end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  std::string field = text.substr(begin, end - begin);
  if (field.size() >= 2 && field.front() == '"' && field.back() == '"') field = field.substr(1, field.size() - 2);
  return field;
}

// The run CSV holds numbers and plain body names: splitting on commas is all it needs (no CSV library in the
// project's dependencies, and a quoted comma inside a body name is not something the simulate command writes).
std::vector<std::string> splitCsvLine(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  for (std::string field; std::getline(stream, field, ',');) fields.push_back(trim(field));
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

Vec3 readVec3(const nlohmann::json& value, const std::string& what) {
  if (!value.is_array() || value.size() != 3) throw Error(what + " must be an array of 3 numbers");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!value[static_cast<std::size_t>(i)].is_number()) throw Error(what + " must be an array of 3 numbers");
    v[i] = value[static_cast<std::size_t>(i)].get<double>();
  }
  if (!v.allFinite()) throw Error(what + " is not finite");
  return v;
}

std::optional<std::string> findMesh(const std::string& meshPath, const std::vector<std::string>& searchFolders,
                                    const fs::path& sceneFolder) {
  const fs::path given(meshPath);
  if (given.is_absolute()) return fs::exists(given) ? std::optional<std::string>(meshPath) : std::nullopt;
  std::vector<fs::path> folders(searchFolders.begin(), searchFolders.end());
  // The scene's folder and its parents: "assets/meshes/x.off" in assets/scenes/s.json resolves from the root.
  fs::path folder = sceneFolder;
  for (int up = 0; up < 4 && !folder.empty(); ++up) {
    folders.push_back(folder);
    if (folder == folder.parent_path()) break;
    folder = folder.parent_path();
  }
  folders.push_back(fs::current_path());
  for (const fs::path& candidateFolder : folders) {
    const fs::path candidate = candidateFolder / given;
    if (fs::is_regular_file(candidate)) return candidate.lexically_normal().string();
  }
  return std::nullopt;
}

/// Column lookup by any of several names (lower case), optionally prefixed by a body name.
class CsvColumns {
 public:
  explicit CsvColumns(const std::vector<std::string>& header) {
    for (std::size_t i = 0; i < header.size(); ++i) m_index[lowerCase(header[i])] = static_cast<int>(i);
  }
  int find(std::initializer_list<const char*> names, const std::string& bodyPrefix = "") const {
    const std::string prefix = lowerCase(bodyPrefix);
    for (const char* name : names) {
      if (prefix.empty()) {
        auto it = m_index.find(name);
        if (it != m_index.end()) return it->second;
        continue;
      }
      for (const char* separator : {".", "_", ":", "/"}) {
        auto it = m_index.find(prefix + separator + name);
        if (it != m_index.end()) return it->second;
      }
    }
    return -1;
  }

 private:
  std::map<std::string, int> m_index;
};

struct PoseColumns {
  int p[3] = {-1, -1, -1};
  int q[4] = {-1, -1, -1, -1};  // w, x, y, z
  bool complete() const {
    return std::all_of(std::begin(p), std::end(p), [](int c) { return c >= 0; }) &&
           std::all_of(std::begin(q), std::end(q), [](int c) { return c >= 0; });
  }
};

PoseColumns poseColumns(const CsvColumns& columns, const std::string& prefix) {
  PoseColumns pose;
  pose.p[0] = columns.find({"px", "x", "pos_x", "position_x"}, prefix);
  pose.p[1] = columns.find({"py", "y", "pos_y", "position_y"}, prefix);
  pose.p[2] = columns.find({"pz", "z", "pos_z", "position_z"}, prefix);
  pose.q[0] = columns.find({"qw", "rw", "quat_w", "orientation_w"}, prefix);
  pose.q[1] = columns.find({"qx", "rx", "quat_x", "orientation_x"}, prefix);
  pose.q[2] = columns.find({"qy", "ry", "quat_y", "orientation_y"}, prefix);
  pose.q[3] = columns.find({"qz", "rz", "quat_z", "orientation_z"}, prefix);
  return pose;
}

/// Where a per-frame series comes from, and how bodies combine into it.
struct SeriesColumn {
  const char* name;
  std::initializer_list<const char*> aliases;
  bool takeMaximum;  // penetration: the deepest body; everything else adds up
};

const SeriesColumn kSeries[] = {
    {"contacts", {"contacts", "contact_count", "num_contacts"}, false},
    {"penetration", {"penetration", "max_penetration", "penetration_m", "depth"}, true},
    {"kinetic_energy", {"kinetic_energy", "ke", "energy"}, false},
    {"ccd_seconds", {"ccd_seconds", "ccd_time", "ccd_s"}, false},
    {"step_seconds", {"step_seconds", "step_time", "step_s"}, false},
};

}  // namespace

RunScene readRunScene(const std::string& path, const std::vector<std::string>& searchFolders, bool resolveMeshes) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open scene '" + path + "': " + std::strerror(errno));
  nlohmann::json json;
  try {
    in >> json;
  } catch (const nlohmann::json::exception& e) {
    throw Error("scene '" + path + "' is not valid JSON: " + std::string(e.what()));
  }
  RunScene scene;
  scene.path = path;
  const fs::path sceneFolder = fs::absolute(fs::path(path)).parent_path();
  try {
    if (!json.is_object() || !json.contains("bodies") || !json["bodies"].is_array()) {
      throw Error("scene '" + path + "' has no \"bodies\" array");
    }
    const bool groundEffect = json.contains("effects") && json["effects"].is_array() &&
                              std::find(json["effects"].begin(), json["effects"].end(), "ground") !=
                                  json["effects"].end();
    if (json.contains("ground") || groundEffect) {
      double height = 0.0;
      if (json.contains("ground") && json["ground"].is_object() && json["ground"].contains("height")) {
        height = json["ground"]["height"].get<double>();
      }
      if (!std::isfinite(height)) throw Error("scene '" + path + "': ground height is not finite");
      scene.groundHeight = height;
    }
    if (json.contains("camera")) {
      const nlohmann::json& c = json["camera"];
      RunCamera camera;
      camera.eye = readVec3(c.at("eye"), "scene '" + path + "': camera eye");
      camera.target = readVec3(c.at("target"), "scene '" + path + "': camera target");
      if (c.contains("up")) camera.up = readVec3(c["up"], "scene '" + path + "': camera up");
      if (c.contains("fov")) camera.fovDegrees = c["fov"].get<double>();
      scene.camera = camera;
    }
    int index = 0;
    for (const nlohmann::json& b : json["bodies"]) {
      RunBody body;
      body.name = b.contains("name") ? b["name"].get<std::string>() : "body" + std::to_string(index);
      const std::string where = "scene '" + path + "', body '" + body.name + "'";
      if (!b.contains("mesh") || !b["mesh"].is_string()) throw Error(where + " has no \"mesh\" file");
      const std::string meshPath = b["mesh"].get<std::string>();
      const std::optional<std::string> found = findMesh(meshPath, searchFolders, sceneFolder);
      if (!found && resolveMeshes) throw Error(where + ": mesh '" + meshPath + "' not found");
      body.meshPath = found ? *found : meshPath;
      if (b.contains("scale")) body.scale = b["scale"].get<double>();
      if (!(body.scale > 0.0) || !std::isfinite(body.scale)) throw Error(where + ": scale must be positive");
      if (b.contains("static")) body.isStatic = b["static"].get<bool>();
      if (b.contains("position")) body.worldFromBody.translation() = readVec3(b["position"], where + ": position");
      if (b.contains("orientation")) {
        const nlohmann::json& q = b["orientation"];
        if (!q.is_array() || q.size() != 4) throw Error(where + ": orientation must be [w, x, y, z]");
        Quat rotation(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>());
        if (!rotation.coeffs().allFinite() || rotation.norm() < 1e-9) throw Error(where + ": bad orientation");
        body.worldFromBody.linear() = rotation.normalized().toRotationMatrix();
      }
      scene.bodies.push_back(std::move(body));
      ++index;
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error("scene '" + path + "': " + std::string(e.what()));
  }
  return scene;
}

void loadRunMeshes(RunScene& ioScene) {
  std::map<std::string, std::shared_ptr<const TriangleMesh>> loaded;
  for (RunBody& body : ioScene.bodies) {
    auto it = loaded.find(body.meshPath);
    if (it == loaded.end()) {
      try {
        it = loaded.emplace(body.meshPath, std::make_shared<const TriangleMesh>(loadMesh(body.meshPath))).first;
      } catch (const Error& e) {
        throw Error("body '" + body.name + "': " + std::string(e.what()));
      }
    }
    body.mesh = it->second;
  }
}

RunFrames readRunFrames(const std::string& csvPath, const RunScene& scene) {
  std::ifstream in(csvPath);
  if (!in) throw Error("cannot open frames '" + csvPath + "': " + std::strerror(errno));
  std::string line;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    if (!trim(line).empty() && line[0] != '#') {
      header = splitCsvLine(line);
      break;
    }
  }
  if (header.empty()) throw Error("frames '" + csvPath + "' is empty");
  const CsvColumns columns(header);
  const int timeColumn = columns.find({"time", "t", "time_s", "sim_time"});
  if (timeColumn < 0) throw Error("frames '" + csvPath + "' has no \"time\" column");
  const int frameColumn = columns.find({"frame", "step"});
  const int bodyColumn = columns.find({"body", "name", "body_name"});
  const std::size_t bodyCount = scene.bodies.size();

  // Per body (wide) or shared (long): which columns hold the pose and the series.
  std::vector<PoseColumns> widePoses;
  PoseColumns longPose;
  if (bodyColumn >= 0) {
    longPose = poseColumns(columns, "");
    if (!longPose.complete()) throw Error("frames '" + csvPath + "' lacks px,py,pz,qw,qx,qy,qz columns");
  } else {
    for (const RunBody& body : scene.bodies) widePoses.push_back(poseColumns(columns, body.name));
  }
  std::map<std::string, std::vector<int>> seriesColumns;  // series -> columns (one per body, or one)
  for (const SeriesColumn& series : kSeries) {
    std::vector<int> found;
    const int shared = columns.find(series.aliases);
    if (shared >= 0) found.push_back(shared);
    if (bodyColumn < 0) {
      for (const RunBody& body : scene.bodies) {
        const int own = columns.find(series.aliases, body.name);
        if (own >= 0) found.push_back(own);
      }
    }
    if (!found.empty()) seriesColumns[series.name] = found;
  }
  std::map<std::string, std::size_t> bodyIndex;
  for (std::size_t i = 0; i < bodyCount; ++i) bodyIndex[scene.bodies[i].name] = i;

  RunFrames frames;
  auto startFrame = [&](int number, double time) {
    frames.frameNumbers.push_back(number);
    frames.times.push_back(time);
    std::vector<Rigid> poses;
    for (const RunBody& body : scene.bodies) poses.push_back(body.worldFromBody);
    frames.worldFromBody.push_back(std::move(poses));
    for (const auto& [name, unused] : seriesColumns) frames.series[name].push_back(0.0);
  };
  auto number = [&](const std::vector<std::string>& row, int column, int lineNumber) {
    const std::string& text = row[static_cast<std::size_t>(column)];
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(value)) {
      throw Error("frames '" + csvPath + "' line " + std::to_string(lineNumber) + ": '" + text + "' in column '" +
                  header[static_cast<std::size_t>(column)] + "' is not a finite number");
    }
    return value;
  };
  auto readPose = [&](const std::vector<std::string>& row, const PoseColumns& pose, int lineNumber) {
    Rigid worldFromBody = Rigid::Identity();
    worldFromBody.translation() =
        Vec3(number(row, pose.p[0], lineNumber), number(row, pose.p[1], lineNumber), number(row, pose.p[2], lineNumber));
    Quat q(number(row, pose.q[0], lineNumber), number(row, pose.q[1], lineNumber), number(row, pose.q[2], lineNumber),
           number(row, pose.q[3], lineNumber));
    if (q.norm() < 1e-9) throw Error("frames '" + csvPath + "' line " + std::to_string(lineNumber) + ": zero quaternion");
    worldFromBody.linear() = q.normalized().toRotationMatrix();
    return worldFromBody;
  };

  int lineNumber = 1;
  double lastKey = std::numeric_limits<double>::quiet_NaN();
  while (std::getline(in, line)) {
    ++lineNumber;
    if (trim(line).empty() || line[0] == '#') continue;
    const std::vector<std::string> row = splitCsvLine(line);
    if (row.size() != header.size()) {
      throw Error("frames '" + csvPath + "' line " + std::to_string(lineNumber) + " has " +
                  std::to_string(row.size()) + " fields, the header " + std::to_string(header.size()) +
                  " (truncated file?)");
    }
    const double time = number(row, timeColumn, lineNumber);
    const double key = frameColumn >= 0 ? number(row, frameColumn, lineNumber) : time;
    const bool newFrame = bodyColumn < 0 || frames.times.empty() || key != lastKey;
    if (newFrame) {
      const int frameNumber = frameColumn >= 0 ? static_cast<int>(std::lround(key))
                                               : static_cast<int>(frames.frameNumbers.size());
      startFrame(frameNumber, time);
    }
    lastKey = key;
    if (bodyColumn >= 0) {
      const std::string& name = row[static_cast<std::size_t>(bodyColumn)];
      auto it = bodyIndex.find(name);
      if (it == bodyIndex.end()) {
        throw Error("frames '" + csvPath + "' line " + std::to_string(lineNumber) + ": body '" + name +
                    "' is not in the scene");
      }
      frames.worldFromBody.back()[it->second] = readPose(row, longPose, lineNumber);
    } else {
      for (std::size_t i = 0; i < bodyCount; ++i) {
        if (widePoses[i].complete()) frames.worldFromBody.back()[i] = readPose(row, widePoses[i], lineNumber);
      }
    }
    for (const SeriesColumn& series : kSeries) {
      auto it = seriesColumns.find(series.name);
      if (it == seriesColumns.end()) continue;
      double& value = frames.series[series.name].back();
      for (int column : it->second) {
        const double v = number(row, column, lineNumber);
        value = series.takeMaximum ? std::max(value, v) : value + v;
      }
    }
  }
  if (frames.times.empty()) throw Error("frames '" + csvPath + "' has a header but no frames");
  if (bodyColumn < 0) {
    bool anyPose = false;
    for (const PoseColumns& pose : widePoses) anyPose = anyPose || pose.complete();
    if (!anyPose && bodyCount > 0) throw Error("frames '" + csvPath + "' has no pose columns for any scene body");
  }
  return frames;
}

RunFolder readRunFolder(const std::string& folder, bool resolveMeshes) {
  if (!fs::is_directory(folder)) throw Error("run folder '" + folder + "' does not exist");
  std::vector<std::string> searchFolders = {folder};
  const fs::path summaryPath = fs::path(folder) / kRunSummaryFile;
  if (fs::exists(summaryPath)) {
    std::ifstream in(summaryPath);
    const nlohmann::json summary = nlohmann::json::parse(in, nullptr, false);
    for (const char* key : {"scene", "scene_path", "scene_file"}) {
      if (!summary.is_discarded() && summary.is_object() && summary.contains(key) && summary[key].is_string()) {
        const fs::path original = fs::absolute(summary[key].get<std::string>()).parent_path();
        searchFolders.push_back(original.string());
        if (original.has_parent_path()) searchFolders.push_back(original.parent_path().string());
        if (original.parent_path().has_parent_path()) searchFolders.push_back(original.parent_path().parent_path().string());
      }
    }
  }
  RunFolder run;
  run.folder = folder;
  run.scene = readRunScene((fs::path(folder) / kRunSceneFile).string(), searchFolders, resolveMeshes);
  run.frames = readRunFrames((fs::path(folder) / kRunFramesFile).string(), run.scene);
  return run;
}

}  // namespace sdfccd::cli
