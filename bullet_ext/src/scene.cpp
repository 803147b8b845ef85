/// @file
/// @brief Scene parsing and validation (see scene.h).
#include "sdfccd/bullet/scene.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

using Json = nlohmann::json;

std::string numberText(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// Reads typed values with one-line errors that name the scene and the key path.
class Reader {
 public:
  Reader(std::string sceneName, std::string baseDir) : m_scene(std::move(sceneName)), m_baseDir(std::move(baseDir)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw Error("scene '" + m_scene + "': " + where + (where.empty() ? "" : " ") + what);
  }

  void checkObject(const Json& j, const std::string& where) const {
    if (!j.is_object()) fail(where.empty() ? "the top level" : where, "must be a JSON object");
  }

  void checkKeys(const Json& j, const std::set<std::string>& allowed, const std::string& where) const {
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (allowed.count(it.key()) == 0) {
        std::string list;
        for (const std::string& k : allowed) list += (list.empty() ? "" : ", ") + k;
        fail(join(where, it.key()), "is not a known key (known: " + list + ")");
      }
    }
  }

  static std::string join(const std::string& where, const std::string& key) {
    return where.empty() ? key : where + "." + key;
  }

  double number(const Json& j, const std::string& key, const std::string& where, double fallback,
                bool required = false) const {
    if (!j.contains(key)) {
      if (required) fail(join(where, key), "is missing");
      return fallback;
    }
    const Json& v = j.at(key);
    if (!v.is_number()) fail(join(where, key), "must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(join(where, key), "must be finite");
    return d;
  }

  int integer(const Json& j, const std::string& key, const std::string& where, int fallback, int lo, int hi) const {
    if (!j.contains(key)) return fallback;
    const Json& v = j.at(key);
    if (!v.is_number_integer()) fail(join(where, key), "must be an integer");
    const long long n = v.get<long long>();
    if (n < lo || n > hi) {
      fail(join(where, key),
           "must be in " + std::to_string(lo) + ".." + std::to_string(hi) + " (got " + std::to_string(n) + ")");
    }
    return static_cast<int>(n);
  }

  bool boolean(const Json& j, const std::string& key, const std::string& where, bool fallback) const {
    if (!j.contains(key)) return fallback;
    if (!j.at(key).is_boolean()) fail(join(where, key), "must be true or false");
    return j.at(key).get<bool>();
  }

  std::string string(const Json& j, const std::string& key, const std::string& where) const {
    if (!j.contains(key)) return {};
    if (!j.at(key).is_string()) fail(join(where, key), "must be a string");
    return j.at(key).get<std::string>();
  }

  std::vector<double> numbers(const Json& j, const std::string& key, const std::string& where,
                              std::size_t count) const {
    const Json& v = j.at(key);
    if (!v.is_array() || v.size() != count)
      fail(join(where, key), "must be an array of " + std::to_string(count) + " numbers");
    std::vector<double> out;
    for (const Json& e : v) {
      if (!e.is_number()) fail(join(where, key), "must be an array of " + std::to_string(count) + " numbers");
      const double d = e.get<double>();
      if (!std::isfinite(d)) fail(join(where, key), "must hold finite numbers");
      out.push_back(d);
    }
    return out;
  }

  Vec3 vec3(const Json& j, const std::string& key, const std::string& where, const Vec3& fallback) const {
    if (!j.contains(key)) return fallback;
    const std::vector<double> v = numbers(j, key, where, 3);
    return Vec3(v[0], v[1], v[2]);
  }

  /// A file path: must exist; relative paths are tried against the cwd, then baseDir and its ancestors.
  std::string file(const Json& j, const std::string& key, const std::string& where) const {
    const std::string given = string(j, key, where);
    if (given.empty()) return {};
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::path(given).is_absolute()) {
      if (fs::is_regular_file(given, ec)) return given;
    } else {
      if (fs::is_regular_file(given, ec)) return given;
      fs::path dir = fs::path(m_baseDir.empty() ? "." : m_baseDir);
      for (int up = 0; up < 4; ++up) {
        const fs::path candidate = dir / given;
        if (fs::is_regular_file(candidate, ec)) return candidate.lexically_normal().string();
        if (!dir.has_parent_path() || dir.parent_path() == dir) break;
        dir = dir.parent_path();
      }
    }
    fail(join(where, key), "names a missing file '" + given + "'");
  }

 private:
  std::string m_scene;
  std::string m_baseDir;
};

ScenePrimitive readPrimitive(const Reader& r, const Json& j, const std::string& where) {
  r.checkObject(j, where);
  r.checkKeys(j, {"type", "half_extents", "radius", "height", "subdivisions"}, where);
  ScenePrimitive p;
  p.type = r.string(j, "type", where);
  if (p.type != "box" && p.type != "sphere" && p.type != "cylinder" && p.type != "bowl") {
    r.fail(Reader::join(where, "type"), "must be box, sphere, cylinder or bowl (got '" + p.type + "')");
  }
  p.halfExtents = r.vec3(j, "half_extents", where, p.halfExtents);
  p.radius = r.number(j, "radius", where, p.radius);
  p.height = r.number(j, "height", where, p.height);
  p.subdivisions = r.integer(j, "subdivisions", where, p.subdivisions, 0, 6);
  if (!(p.halfExtents.minCoeff() > 0) || !(p.radius > 0) || !(p.height > 0)) {
    r.fail(where, "sizes must be positive");
  }
  return p;
}

SceneBody readBody(const Reader& r, const Json& j, const std::string& where, int index) {
  r.checkObject(j, where);
  r.checkKeys(j,
              {"name", "mesh", "primitive", "sdf", "shell", "scale", "mass", "position", "orientation", "velocity",
               "angular_velocity", "static", "points", "resolution", "padding"},
              where);
  SceneBody b;
  b.name = r.string(j, "name", where);
  if (b.name.empty()) b.name = "body" + std::to_string(index);
  b.isStatic = r.boolean(j, "static", where, false);
  b.mesh = r.file(j, "mesh", where);
  if (j.contains("primitive")) b.primitive = readPrimitive(r, j.at("primitive"), Reader::join(where, "primitive"));
  if (b.mesh.empty() == !b.primitive.has_value()) r.fail(where, "needs exactly one of \"mesh\" and \"primitive\"");
  b.sdf = r.file(j, "sdf", where);
  b.shell = r.file(j, "shell", where);
  if (b.sdf.empty() != b.shell.empty()) r.fail(where, "\"sdf\" and \"shell\" go together");
  if (!b.sdf.empty() && b.mesh.empty()) r.fail(where, "\"sdf\" and \"shell\" need a \"mesh\"");
  b.scale = r.number(j, "scale", where, 1.0);
  if (!(b.scale > 0)) r.fail(Reader::join(where, "scale"), "must be > 0 (got " + numberText(b.scale) + ")");
  b.mass = r.number(j, "mass", where, 1.0, !b.isStatic);
  if (!b.isStatic && !(b.mass > 0)) r.fail(Reader::join(where, "mass"), "must be > 0 (got " + numberText(b.mass) + ")");
  b.position = r.vec3(j, "position", where, Vec3::Zero());
  if (j.contains("orientation")) {
    const std::vector<double> q = r.numbers(j, "orientation", where, 4);
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (std::abs(norm - 1.0) > 1e-6) {
      r.fail(Reader::join(where, "orientation"),
             "must be a unit quaternion w, x, y, z (norm " + numberText(norm) + ")");
    }
    b.orientation = Quat(q[0], q[1], q[2], q[3]).normalized();
  }
  b.velocity = r.vec3(j, "velocity", where, Vec3::Zero());
  b.angularVelocity = r.vec3(j, "angular_velocity", where, Vec3::Zero());
  b.points = r.integer(j, "points", where, 0, 0, 10000000);
  b.resolution = r.integer(j, "resolution", where, 64, 4, 1024);
  b.padding = r.integer(j, "padding", where, 4, 1, 64);
  return b;
}

}  // namespace

std::string Scene::effectList() const {
  std::string out;
  for (const std::string& e : effects) out += (out.empty() ? "" : ",") + e;
  return out;
}

Scene parseScene(const std::string& text, const std::string& name, const std::string& baseDir) {
  const Reader r(name, baseDir);
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::exception& e) {  // parse errors, and number overflow (1e999) as out_of_range
    std::string what = e.what();
    r.fail("", "is not valid JSON (" + what.substr(0, what.find('\n')) + ")");
  }
  r.checkObject(root, "");
  r.checkKeys(root,
              {"name", "description", "timestep", "frames", "gravity", "effects", "ground", "contact", "bodies",
               "sleeping", "camera"},
              "");
  Scene s;
  s.name = r.string(root, "name", "");
  (void)r.string(root, "description", "");
  s.timestep = r.number(root, "timestep", "", s.timestep);
  if (!(s.timestep > 0) || s.timestep > 1.0)
    r.fail("timestep", "must be in (0, 1] s (got " + numberText(s.timestep) + ")");
  s.frames = r.integer(root, "frames", "", s.frames, 1, 100000000);
  s.gravity = r.vec3(root, "gravity", "", s.gravity);
  s.sleeping = r.boolean(root, "sleeping", "", s.sleeping);
  if (root.contains("effects")) {
    const Json& effects = root.at("effects");
    if (!effects.is_array()) r.fail("effects", "must be an array of strings");
    for (const Json& e : effects) {
      if (!e.is_string()) r.fail("effects", "must be an array of strings");
      const std::string effect = e.get<std::string>();
      if (effect != "gravity" && effect != "ground" && effect != "damping" && effect != "rotation" &&
          effect != "friction") {
        r.fail("effects",
               "has an unknown effect '" + effect + "' (known: damping, friction, gravity, ground, rotation)");
      }
      s.effects.insert(effect);
    }
  }
  if (root.contains("ground")) {
    const Json& g = root.at("ground");
    r.checkObject(g, "ground");
    r.checkKeys(g, {"height"}, "ground");
    s.groundHeight = r.number(g, "height", "ground", 0.0);
  }
  if (root.contains("camera")) {
    // Read by the renderer (sdfccd simulate --render, sdfccd render); checked here so a typo fails early.
    const Json& cam = root.at("camera");
    r.checkObject(cam, "camera");
    r.checkKeys(cam, {"eye", "target", "up", "fov"}, "camera");
    if (!cam.contains("eye") || !cam.contains("target")) r.fail("camera", "needs \"eye\" and \"target\"");
    const Vec3 eye = r.vec3(cam, "eye", "camera", Vec3::Zero());
    const Vec3 target = r.vec3(cam, "target", "camera", Vec3::Zero());
    if ((eye - target).norm() <= 0.0) r.fail("camera", "eye and target must differ");
    (void)r.vec3(cam, "up", "camera", Vec3::UnitY());
    const double fov = r.number(cam, "fov", "camera", 45.0);
    if (!(fov > 0.0 && fov < 180.0)) r.fail("camera.fov", "must be in (0, 180) degrees (got " + numberText(fov) + ")");
  }
  if (root.contains("contact")) {
    const Json& c = root.at("contact");
    r.checkObject(c, "contact");
    r.checkKeys(c,
                {"model", "stiffness", "damping", "friction", "subintervals", "toi_clamp", "toi_depth_cells", "tree",
                 "force_timing", "direction"},
                "contact");
    const std::string model = r.string(c, "model", "contact");
    if (model == "discrete") {
      s.contact.model = PenaltyModel::Discrete;
    } else if (model.empty() || model == "continuous") {
      s.contact.model = PenaltyModel::Continuous;
    } else {
      r.fail("contact.model", "must be continuous or discrete (got '" + model + "')");
    }
    s.contact.stiffness = r.number(c, "stiffness", "contact", s.contact.stiffness);
    s.contact.damping = r.number(c, "damping", "contact", s.contact.damping);
    if (!(s.contact.stiffness > 0)) r.fail("contact.stiffness", "must be > 0");
    if (!(s.contact.damping >= 0)) r.fail("contact.damping", "must be >= 0");
    s.contact.friction = r.number(c, "friction", "contact", s.contact.friction);
    if (!(s.contact.friction >= 0)) r.fail("contact.friction", "must be >= 0");
    const std::string timing = r.string(c, "force_timing", "contact");
    if (timing == "next_step") {
      s.contact.forceTiming = SdfccdForceTiming::NextStep;
    } else if (timing.empty() || timing == "same_step") {
      s.contact.forceTiming = SdfccdForceTiming::SameStep;
    } else {
      r.fail("contact.force_timing", "must be same_step or next_step (got '" + timing + "')");
    }
    const std::string direction = r.string(c, "direction", "contact");
    if (direction == "field_gradient") {
      s.contact.direction = PenaltyDirection::FieldGradient;
    } else if (direction.empty() || direction == "shell_normal") {
      s.contact.direction = PenaltyDirection::ShellNormal;
    } else {
      r.fail("contact.direction", "must be shell_normal or field_gradient (got '" + direction + "')");
    }
    s.contact.subintervals = r.integer(c, "subintervals", "contact", s.contact.subintervals, 1, 1000);
    s.contact.timeOfImpactClamp = r.boolean(c, "toi_clamp", "contact", s.contact.timeOfImpactClamp);
    s.contact.toiDepthCells = r.number(c, "toi_depth_cells", "contact", s.contact.toiDepthCells);
    if (!(s.contact.toiDepthCells >= 0)) r.fail("contact.toi_depth_cells", "must be >= 0");
    s.contact.useTree = r.boolean(c, "tree", "contact", s.contact.useTree);
  }
  if (!root.contains("bodies") || !root.at("bodies").is_array() || root.at("bodies").empty()) {
    r.fail("bodies", "must be a non-empty array");
  }
  int index = 0;
  std::set<std::string> names;
  for (const Json& b : root.at("bodies")) {
    s.bodies.push_back(readBody(r, b, "bodies[" + std::to_string(index) + "]", index));
    if (!names.insert(s.bodies.back().name).second) {
      r.fail("bodies[" + std::to_string(index) + "].name", "repeats '" + s.bodies.back().name + "'");
    }
    ++index;
  }
  return s;
}

Scene loadScene(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("scene '" + path + "': cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  Scene s = parseScene(text.str(), path, std::filesystem::path(path).parent_path().string());
  s.path = path;
  if (s.name.empty()) s.name = std::filesystem::path(path).stem().string();
  return s;
}

}  // namespace sdfccd
