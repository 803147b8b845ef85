/// @file
/// @brief RunFolder: scene.json and frames.csv of a saved run, read by column name.
#include "cli/run_folder.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/csv_fields.h"
#include "sdfccd/error.h"
#include "sdfccd/mesh/mass_properties.h"
#include "sdfccd/model/mesh_file.h"
#include "sdfccd/model/scene.h"

namespace sdfccd::cli {

namespace fs = std::filesystem;

namespace {

/// The value of a CSV field that is a complete number (finite or not); NaN when it is not a number at all.
double finiteValue(const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || *end != '\0') return std::numeric_limits<double>::quiet_NaN();
  return value;
}

/// True when a field of the row is a number that is not finite ("nan", "inf", "-nan", ...); the column
/// `textColumn` (a body name, which may read "nan") is skipped.
bool holdsNonFinite(const std::vector<std::string>& row, int textColumn) {
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (static_cast<int>(i) == textColumn) continue;
    const std::string& field = row[i];
    char* end = nullptr;
    const double value = std::strtod(field.c_str(), &end);
    if (!field.empty() && end != field.c_str() && *end == '\0' && !std::isfinite(value)) return true;
  }
  return false;
}

std::string lowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string trimmedField(const std::string& text) {
  std::size_t begin = 0;
  std::size_t end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  std::string field = text.substr(begin, end - begin);
  if (field.size() >= 2 && field.front() == '"' && field.back() == '"') field = field.substr(1, field.size() - 2);
  return field;
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
  std::initializer_list<std::pair<const char*, double>> aliases;  // column name, factor to the series' unit
  bool takeMaximum;  // penetration: the deepest body; everything else adds up
};

const SeriesColumn kSeries[] = {
    {"contacts", {{"contacts", 1.0}, {"contact_count", 1.0}, {"num_contacts", 1.0}}, false},
    {"penetration",
     {{"penetration", 1.0},
      {"max_penetration", 1.0},
      {"penetration_m", 1.0},
      {"penetration_cells", 1.0},
      {"max_penetration_cells", 1.0}},
     true},
    {"kinetic_energy", {{"kinetic_energy", 1.0}, {"ke", 1.0}}, false},
    {"ccd_seconds", {{"ccd_seconds", 1.0}, {"ccd_s", 1.0}, {"ccd_ms", 1e-3}}, false},
    {"step_seconds", {{"step_seconds", 1.0}, {"step_s", 1.0}, {"step_ms", 1e-3}}, false},
};

}  // namespace

RunScene readRunScene(const std::string& path, const std::vector<std::string>& searchFolders, bool resolveMeshes) {
  SceneLoadSettings load;
  load.searchFolders = searchFolders;
  load.requireFiles = resolveMeshes;
  const Scene scene = loadScene(path, load);
  RunScene run;
  run.path = path;
  // The ground is drawn when it is simulated: the "ground" effect.
  if (scene.has("ground")) run.groundHeight = scene.groundHeight;
  run.camera = scene.camera;
  for (const SceneBody& b : scene.bodies) {
    RunBody body;
    body.name = b.name;
    body.meshPath = b.mesh;
    body.primitive = b.primitive;
    body.scale = b.scale;
    body.isStatic = b.isStatic;
    body.mass = b.isStatic ? 0.0 : b.mass;
    body.positionAtStart = b.position;
    body.orientationAtStart = b.orientation;
    body.worldFromBody.linear() = body.orientationAtStart.toRotationMatrix();
    body.worldFromBody.translation() = body.positionAtStart;
    run.bodies.push_back(std::move(body));
  }
  return run;
}

Rigid modelFromBodyOf(const TriangleMesh& scaledMeshInModel, Vec3* outUnitDensityPrincipalMoments,
                      double* outUnitDensityMass) {
  MassPropertiesSettings unitDensity;
  unitDensity.density = 1.0;
  const MassProperties inModel = computeMassProperties(scaledMeshInModel, unitDensity);
  const BodyFrame frame = bodyFrameOf(inModel);  // the same rule as BodyModel
  if (outUnitDensityPrincipalMoments != nullptr) *outUnitDensityPrincipalMoments = frame.principalMoments();
  if (outUnitDensityMass != nullptr) *outUnitDensityMass = inModel.mass;
  return frame.modelFromBody;
}

void loadRunMeshes(RunScene& ioScene) {
  struct Loaded {
    std::shared_ptr<const TriangleMesh> meshInBody;
    Rigid modelFromBody;
    Vec3 unitMoments;
    double unitMass = 1.0;
  };
  std::map<std::string, Loaded> loaded;  // by mesh file or primitive, and scale
  for (RunBody& body : ioScene.bodies) {
    std::ostringstream key;
    key.precision(17);
    if (body.primitive) {
      const ScenePrimitive& p = *body.primitive;
      key << "primitive " << p.type << " " << p.halfExtents.transpose() << " " << p.radius << " " << p.height << " "
          << p.subdivisions;
    } else {
      key << "file " << body.meshPath;
    }
    key << " scale " << body.scale;
    auto it = loaded.find(key.str());
    if (it == loaded.end()) {
      try {
        TriangleMesh mesh = body.primitive ? makePrimitiveMesh(*body.primitive) : loadMeshFile(body.meshPath);
        for (Vec3& v : mesh.vertices) v *= body.scale;
        Loaded entry;
        entry.modelFromBody = modelFromBodyOf(mesh, &entry.unitMoments, &entry.unitMass);
        const Rigid bodyFromModel = entry.modelFromBody.inverse();
        for (Vec3& v : mesh.vertices) v = bodyFromModel * v;
        entry.meshInBody = std::make_shared<const TriangleMesh>(std::move(mesh));
        it = loaded.emplace(key.str(), std::move(entry)).first;
      } catch (const Error& e) {
        throw Error("body '" + body.name + "': " + std::string(e.what()));
      }
    }
    const Loaded& entry = it->second;
    body.mesh = entry.meshInBody;
    body.principalInertia = entry.unitMoments * (body.mass / entry.unitMass);
    body.worldFromBody = worldFromBodyAt(entry.modelFromBody, body.positionAtStart, body.orientationAtStart);
  }
}

RunFrames readRunFrames(const std::string& csvPath, const RunScene& scene) {
  std::ifstream in(csvPath);
  if (!in) throw Error("cannot open frames '" + csvPath + "': " + std::strerror(errno));
  std::string line;
  std::vector<std::string> header;
  int recordLine = 0;  // the last line read
  while (readCsvRecord(in, line, recordLine)) {
    if (!trimmedField(line).empty() && line[0] != '#') {
      header = splitCsvRecord(line);  // quoted: body names may hold commas (csv_fields.h)
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
  // Series: the columns behind each (one shared, or one per body) with the factor to the series' unit.
  std::map<std::string, std::vector<std::pair<int, double>>> seriesColumns;
  RunFrames frames;
  for (const SeriesColumn& series : kSeries) {
    std::vector<std::pair<int, double>> found;
    for (const auto& [alias, factor] : series.aliases) {
      const int shared = columns.find({alias});
      if (shared >= 0) {
        found.emplace_back(shared, factor);
        frames.seriesSource[series.name] = alias;
        break;
      }
    }
    if (bodyColumn < 0) {
      for (const RunBody& body : scene.bodies) {
        for (const auto& [alias, factor] : series.aliases) {
          const int own = columns.find({alias}, body.name);
          if (own >= 0) {
            found.emplace_back(own, factor);
            frames.seriesSource[series.name] = std::string("<body>.") + alias;
            break;
          }
        }
      }
    }
    if (!found.empty()) seriesColumns[series.name] = found;
  }
  // Velocities (world frame) for the kinetic energy when no column gives it and the meshes are loaded.
  struct VelocityColumns {
    int v[3] = {-1, -1, -1};
    int w[3] = {-1, -1, -1};
  };
  std::vector<VelocityColumns> velocities;
  bool computeEnergy = seriesColumns.count("kinetic_energy") == 0 && bodyCount > 0;
  for (const RunBody& body : scene.bodies) {
    const std::string prefix = bodyColumn >= 0 ? std::string() : body.name;
    VelocityColumns c;
    const char* names[6] = {"vx", "vy", "vz", "wx", "wy", "wz"};
    for (int k = 0; k < 3; ++k) {
      c.v[k] = columns.find({names[k]}, prefix);
      c.w[k] = columns.find({names[3 + k]}, prefix);
      computeEnergy = computeEnergy && (body.isStatic || (c.v[k] >= 0 && c.w[k] >= 0));
    }
    computeEnergy = computeEnergy && (body.isStatic || body.mesh != nullptr);
    velocities.push_back(c);
  }
  if (computeEnergy) frames.seriesSource["kinetic_energy"] = "computed from velocities, masses and inertias";

  std::map<std::string, std::size_t> bodyIndex;
  for (std::size_t i = 0; i < bodyCount; ++i) bodyIndex[scene.bodies[i].name] = i;

  auto startFrame = [&](int number, double time) {
    frames.frameNumbers.push_back(number);
    frames.times.push_back(time);
    std::vector<Rigid> poses;
    for (const RunBody& body : scene.bodies) poses.push_back(body.worldFromBody);
    frames.worldFromBody.push_back(std::move(poses));
    for (const auto& [name, unused] : seriesColumns) frames.series[name].push_back(0.0);
    if (computeEnergy) frames.series["kinetic_energy"].push_back(0.0);
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
    worldFromBody.translation() = Vec3(number(row, pose.p[0], lineNumber), number(row, pose.p[1], lineNumber),
                                       number(row, pose.p[2], lineNumber));
    Quat q(number(row, pose.q[0], lineNumber), number(row, pose.q[1], lineNumber), number(row, pose.q[2], lineNumber),
           number(row, pose.q[3], lineNumber));
    if (q.norm() < 1e-9)
      throw Error("frames '" + csvPath + "' line " + std::to_string(lineNumber) + ": zero quaternion");
    worldFromBody.linear() = q.normalized().toRotationMatrix();
    return worldFromBody;
  };

  // Translational plus rotational energy: 0.5 m v^2 + 0.5 w_body . (I_body w_body), as the simulation reports it.
  auto kineticEnergy = [&](const std::vector<std::string>& row, std::size_t body, int lineNumber) {
    const RunBody& b = scene.bodies[body];
    if (b.isStatic) return 0.0;
    const VelocityColumns& c = velocities[body];
    const Vec3 v(number(row, c.v[0], lineNumber), number(row, c.v[1], lineNumber), number(row, c.v[2], lineNumber));
    const Vec3 w(number(row, c.w[0], lineNumber), number(row, c.w[1], lineNumber), number(row, c.w[2], lineNumber));
    const Vec3 wInBody = frames.worldFromBody.back()[body].linear().transpose() * w;
    return 0.5 * b.mass * v.squaredNorm() + 0.5 * wInBody.dot(b.principalInertia.cwiseProduct(wInBody));
  };

  auto dropLastFrame = [&] {
    frames.frameNumbers.pop_back();
    frames.times.pop_back();
    frames.worldFromBody.pop_back();
    for (auto& [name, values] : frames.series) {
      if (!values.empty()) values.pop_back();
    }
  };

  double lastKey = std::numeric_limits<double>::quiet_NaN();
  while (readCsvRecord(in, line, recordLine)) {
    const int lineNumber = recordLine;
    if (trimmedField(line).empty() || line[0] == '#') continue;
    const std::vector<std::string> row = splitCsvRecord(line);
    if (row.size() != header.size()) {
      throw Error("frames '" + csvPath + "' line " + std::to_string(lineNumber) + " has " + std::to_string(row.size()) +
                  " fields, the header " + std::to_string(header.size()) + " (truncated file?)");
    }
    // A run that went non-finite (simulate stops there, exit code 3) ends in a row holding nan or inf: the frames
    // before it are the run, so they are shown, with one line saying where the run stopped.
    if (!frames.times.empty() && holdsNonFinite(row, bodyColumn)) {
      if (bodyColumn >= 0 && frameColumn >= 0 && finiteValue(row[static_cast<std::size_t>(frameColumn)]) == lastKey) {
        dropLastFrame();  // the long layout's partial frame
      }
      std::fprintf(stderr,
                   "sdfccd: warning: frames '%s' line %d: a non-finite state; the %zu frames before it are used\n",
                   csvPath.c_str(), lineNumber, frames.times.size());
      break;
    }
    const double time = number(row, timeColumn, lineNumber);
    const double key = frameColumn >= 0 ? number(row, frameColumn, lineNumber) : time;
    const bool newFrame = bodyColumn < 0 || frames.times.empty() || key != lastKey;
    if (newFrame) {
      const int frameNumber =
          frameColumn >= 0 ? static_cast<int>(std::lround(key)) : static_cast<int>(frames.frameNumbers.size());
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
      if (computeEnergy) frames.series["kinetic_energy"].back() += kineticEnergy(row, it->second, lineNumber);
    } else {
      for (std::size_t i = 0; i < bodyCount; ++i) {
        if (widePoses[i].complete()) frames.worldFromBody.back()[i] = readPose(row, widePoses[i], lineNumber);
        if (computeEnergy) frames.series["kinetic_energy"].back() += kineticEnergy(row, i, lineNumber);
      }
    }
    for (const SeriesColumn& series : kSeries) {
      auto it = seriesColumns.find(series.name);
      if (it == seriesColumns.end()) continue;
      double& value = frames.series[series.name].back();
      for (const auto& [column, factor] : it->second) {
        const double v = factor * number(row, column, lineNumber);
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

RunFolder readRunFolder(const std::string& folder, bool loadMeshes) {
  if (!fs::is_directory(folder)) throw Error("run folder '" + folder + "' does not exist");
  std::vector<std::string> searchFolders = {folder};
  std::string originalScene;
  const fs::path summaryPath = fs::path(folder) / kRunSummaryFile;
  if (fs::exists(summaryPath)) {
    std::ifstream in(summaryPath);
    const nlohmann::json summary = nlohmann::json::parse(in, nullptr, false);
    for (const char* key : {"scene", "scene_path", "scene_file"}) {
      if (summary.is_discarded() || !summary.is_object() || !summary.contains(key) || !summary[key].is_string()) {
        continue;
      }
      // A relative path was relative to where simulate ran: try there (the current folder) and beside the run.
      const fs::path given = summary[key].get<std::string>();
      for (const fs::path& candidate : {given, fs::path(folder) / given, fs::path(folder).parent_path() / given,
                                        fs::path(folder).parent_path().parent_path() / given}) {
        if (fs::is_regular_file(candidate)) {
          originalScene = candidate.string();
          break;
        }
      }
      // Like the scene loader: the original scene's folder and its ancestors.
      fs::path original = fs::absolute(originalScene.empty() ? given : fs::path(originalScene)).parent_path();
      for (int up = 0; up < 4 && !original.empty(); ++up) {
        searchFolders.push_back(original.string());
        if (original == original.parent_path()) break;
        original = original.parent_path();
      }
      break;
    }
  }
  std::string scenePath = (fs::path(folder) / kRunSceneFile).string();
  if (!fs::exists(scenePath)) {
    if (originalScene.empty()) {
      throw Error("run folder '" + folder + "' has no scene.json, and summary.json names no scene file found");
    }
    scenePath = originalScene;
  }
  RunFolder run;
  run.folder = folder;
  run.scene = readRunScene(scenePath, searchFolders, loadMeshes);
  if (loadMeshes) loadRunMeshes(run.scene);
  run.frames = readRunFrames((fs::path(folder) / kRunFramesFile).string(), run.scene);
  return run;
}

}  // namespace sdfccd::cli
