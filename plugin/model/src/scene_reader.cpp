/// @file
/// @brief The scene reader: parseScene and loadScene (scene.h), on the shared strict-JSON helpers
/// (detail/json_reader.h).
#include <cmath>
#include <filesystem>

#include "sdfccd/error.h"
#include "sdfccd/model/detail/guard_reader.h"
#include "sdfccd/model/detail/json_reader.h"
#include "sdfccd/model/scene.h"

namespace sdfccd {
namespace {

using detail::Json;
using Reader = detail::JsonReader;

// Plausible ranges of scene quantities (SI units). A value outside is a typo or an absurd setting: refused up
// front with one line naming the key, before it can blow a run up (stiffness, damping or friction 1e12 or a mass
// of 1e-30 run to 1e9..1e24 J, a mass of 1e30 ends in NaN). Each bound is orders of magnitude beyond the shipped
// scenes and the textbook tests.
constexpr double kMinMass = 1e-6;              // kg (a milligram)
constexpr double kMaxMass = 1e6;               // kg (a thousand tonnes)
constexpr double kMinLength = 1e-6;            // m, sizes and scales
constexpr double kMaxLength = 1e4;             // m
constexpr double kMaxCoordinate = 1e6;         // m, positions and the ground height
constexpr double kMaxSpeed = 1e4;              // m/s (start velocities)
constexpr double kMaxAngularSpeed = 1e4;       // rad/s
constexpr double kMaxGravity = 1e4;            // m/s^2 per component (about 1000 g)
constexpr double kMinTimestep = 1e-7;          // s
constexpr double kMaxFriction = 10.0;          // mu
constexpr double kMaxRestitution = 1.0;        // more would create energy on every bounce
constexpr double kMaxStiffness = 1e9;          // N/m per point (default 2000)
constexpr double kMaxStiffnessPerArea = 1e13;  // N/m^3 (default 1e7)
constexpr double kMaxDamping = 1e6;            // N s/m per point (default 5)
constexpr double kMaxToiDepthCells = 100.0;    // field cells

ScenePrimitive readPrimitive(const Reader& r, const Json& j, const std::string& where) {
  r.checkObject(j, where);
  r.checkKeys(j, {"type", "half_extents", "radius", "height", "subdivisions"}, where);
  ScenePrimitive p;
  p.type = r.string(j, "type", where);
  if (p.type != "box" && p.type != "sphere" && p.type != "cylinder" && p.type != "bowl") {
    r.fail(Reader::join(where, "type"), "must be box, sphere, cylinder or bowl (got '" + p.type + "')");
  }
  p.halfExtents = r.vec3(j, "half_extents", where, p.halfExtents);
  if (!(p.halfExtents.minCoeff() >= kMinLength) || !(p.halfExtents.maxCoeff() <= kMaxLength)) {
    r.fail(Reader::join(where, "half_extents"),
           "must be in [" + Reader::numberText(kMinLength) + ", " + Reader::numberText(kMaxLength) + "] m");
  }
  p.radius = r.ranged(j, "radius", where, p.radius, kMinLength, kMaxLength);
  p.height = r.ranged(j, "height", where, p.height, kMinLength, kMaxLength);
  p.subdivisions = r.integer(j, "subdivisions", where, p.subdivisions, 0, 6);
  return p;
}

SceneBody readBody(const Reader& r, const Json& j, const std::string& where, int index) {
  r.checkObject(j, where);
  r.checkKeys(j,
              {"name", "mesh", "primitive", "sdf", "shell", "scale", "mass", "position", "orientation", "velocity",
               "angular_velocity", "static", "kinematic", "points", "resolution", "padding", "friction", "restitution"},
              where);
  SceneBody b;
  b.name = r.string(j, "name", where);
  if (b.name.empty()) b.name = "body" + std::to_string(index);
  b.isStatic = r.boolean(j, "static", where, false);
  b.kinematic = r.boolean(j, "kinematic", where, false);
  if (b.isStatic && b.kinematic) r.fail(Reader::join(where, "kinematic"), "and \"static\" are exclusive");
  b.mesh = r.file(j, "mesh", where);
  if (j.contains("primitive")) b.primitive = readPrimitive(r, j.at("primitive"), Reader::join(where, "primitive"));
  if (b.mesh.empty() == !b.primitive.has_value()) r.fail(where, "needs exactly one of \"mesh\" and \"primitive\"");
  b.sdf = r.file(j, "sdf", where);
  b.shell = r.file(j, "shell", where);
  if (b.sdf.empty() != b.shell.empty()) r.fail(where, "\"sdf\" and \"shell\" go together");
  if (!b.sdf.empty() && b.mesh.empty()) r.fail(where, "\"sdf\" and \"shell\" need a \"mesh\"");
  b.scale = r.ranged(j, "scale", where, 1.0, kMinLength, kMaxLength);
  b.mass = r.number(j, "mass", where, 1.0, !b.isStatic && !b.kinematic);
  if (!b.isStatic && !b.kinematic && !(b.mass > 0))
    r.fail(Reader::join(where, "mass"), "must be > 0 (got " + Reader::numberText(b.mass) + ")");
  if (!b.isStatic && !b.kinematic) b.mass = r.ranged(j, "mass", where, b.mass, kMinMass, kMaxMass);
  b.position = r.boundedVec3(j, "position", where, Vec3::Zero(), kMaxCoordinate);
  if (j.contains("orientation")) b.orientation = r.unitQuaternion(j, "orientation", where);
  b.velocity = r.vec3(j, "velocity", where, Vec3::Zero());
  if (!(b.velocity.norm() <= kMaxSpeed)) {
    r.fail(Reader::join(where, "velocity"), "must be at most " + Reader::numberText(kMaxSpeed) + " m/s (got " +
                                                Reader::numberText(b.velocity.norm()) + ")");
  }
  b.angularVelocity = r.vec3(j, "angular_velocity", where, Vec3::Zero());
  if (!(b.angularVelocity.norm() <= kMaxAngularSpeed)) {
    r.fail(Reader::join(where, "angular_velocity"), "must be at most " + Reader::numberText(kMaxAngularSpeed) +
                                                        " rad/s (got " + Reader::numberText(b.angularVelocity.norm()) +
                                                        ")");
  }
  b.friction = r.ranged(j, "friction", where, b.friction, 0.0, kMaxFriction);
  b.restitution = r.ranged(j, "restitution", where, b.restitution, 0.0, kMaxRestitution);
  b.points = r.integer(j, "points", where, 0, 0, 10000000);
  b.pointsGiven = j.contains("points");
  b.resolution = r.integer(j, "resolution", where, 64, 4, 1024);
  b.padding = r.integer(j, "padding", where, 4, 1, 64);
  return b;
}

/// contact.solver: Bullet's constraint solver in solver mode. Penalty mode answers its contacts itself, so naming a
/// solver there is a mistake worth a line (as contact.model discrete is in solver mode).
void readContactSolver(const Reader& r, const Json& c, SceneContact& contact) {
  const std::string solver = r.string(c, "solver", "contact");
  if (solver.empty()) return;  // absent: SceneContact's default (mlcp)
  if (solver == "mlcp") {
    contact.solver = ContactSolver::Mlcp;
  } else if (solver == "sequential_impulse") {
    contact.solver = ContactSolver::SequentialImpulse;
  } else if (solver == "nncg") {
    contact.solver = ContactSolver::Nncg;
  } else {
    r.fail("contact.solver", "must be mlcp, sequential_impulse or nncg (got '" + solver + "')");
  }
  if (contact.mode != SdfccdContactMode::Solver) {
    r.fail("contact.solver", "applies to solver mode only (contact.mode is penalty)");
  }
}

}  // namespace

SceneGuard detail::readGuard(const JsonReader& r, const Json& g) {
  r.checkObject(g, "guard");
  r.checkKeys(g, {"energy_factor", "max_speed", "extent_factor", "action"}, "guard");
  SceneGuard guard;
  auto atLeast = [&](const char* key, double fallback, double lo) {
    const double v = r.number(g, key, "guard", fallback);
    if (!(v >= lo)) {
      r.fail(JsonReader::join("guard", key),
             "must be >= " + JsonReader::numberText(lo) + " (got " + JsonReader::numberText(v) + ")");
    }
    return v;
  };
  guard.energyFactor = atLeast("energy_factor", guard.energyFactor, 1.0);
  guard.maxSpeed = atLeast("max_speed", guard.maxSpeed, 1.0);
  guard.extentFactor = atLeast("extent_factor", guard.extentFactor, 1.0);
  const std::string action = r.string(g, "action", "guard");
  if (action == "report") {
    guard.action = GuardAction::Report;
  } else if (action == "off") {
    guard.action = GuardAction::Off;
  } else if (!action.empty() && action != "stop") {
    r.fail("guard.action", "must be stop, report or off (got '" + action + "')");
  }
  return guard;
}

std::string Scene::effectList() const {
  std::string out;
  for (const std::string& e : effects) out += (out.empty() ? "" : ",") + e;
  return out;
}

Scene parseScene(const std::string& text, const std::string& name, const std::string& baseDir,
                 const SceneLoadSettings& settings) {
  const Reader r(name, detail::SceneFileSearch{baseDir, settings.searchFolders, settings.requireFiles});
  const Json root = r.parseObject(text);
  r.checkKeys(root,
              {"name", "description", "timestep", "frames", "gravity", "effects", "ground", "contact", "bodies",
               "sleeping", "camera", "guard"},
              "");
  Scene s;
  s.name = r.string(root, "name", "");
  (void)r.string(root, "description", "");
  s.timestep = r.number(root, "timestep", "", s.timestep);
  if (!(s.timestep >= kMinTimestep) || s.timestep > 1.0) {
    r.fail("timestep",
           "must be in [" + Reader::numberText(kMinTimestep) + ", 1] s (got " + Reader::numberText(s.timestep) + ")");
  }
  s.frames = r.integer(root, "frames", "", s.frames, 1, 100000000);
  s.gravity = r.boundedVec3(root, "gravity", "", s.gravity, kMaxGravity);
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
    r.checkKeys(g, {"height", "friction", "restitution"}, "ground");
    s.groundHeight = r.ranged(g, "height", "ground", 0.0, -kMaxCoordinate, kMaxCoordinate);
    s.groundFriction = r.ranged(g, "friction", "ground", s.groundFriction, 0.0, kMaxFriction);
    s.groundRestitution = r.ranged(g, "restitution", "ground", s.groundRestitution, 0.0, 1.0);
  }
  if (root.contains("camera")) {
    // Read by the renderer (sdfccd simulate --render, sdfccd render); checked here so a typo fails early.
    const Json& cam = root.at("camera");
    r.checkObject(cam, "camera");
    r.checkKeys(cam, {"eye", "target", "up", "fov"}, "camera");
    if (!cam.contains("eye") || !cam.contains("target")) r.fail("camera", "needs \"eye\" and \"target\"");
    SceneCamera camera;
    camera.eye = r.vec3(cam, "eye", "camera", Vec3::Zero());
    camera.target = r.vec3(cam, "target", "camera", Vec3::Zero());
    if ((camera.eye - camera.target).norm() <= 0.0) r.fail("camera", "eye and target must differ");
    camera.up = r.vec3(cam, "up", "camera", camera.up);
    camera.fovDegrees = r.number(cam, "fov", "camera", camera.fovDegrees);
    if (!(camera.fovDegrees > 0.0 && camera.fovDegrees < 180.0)) {
      r.fail("camera.fov", "must be in (0, 180) degrees (got " + Reader::numberText(camera.fovDegrees) + ")");
    }
    s.camera = camera;
  }
  if (root.contains("contact")) {
    const Json& c = root.at("contact");
    r.checkObject(c, "contact");
    r.checkKeys(c,
                {"model", "stiffness", "stiffness_per_area", "damping", "damping_ratio", "friction", "friction_model",
                 "subintervals", "toi_clamp", "toi_depth_cells", "tree", "force_timing", "direction", "mode", "solver"},
                "contact");
    const std::string model = r.string(c, "model", "contact");
    if (model == "discrete") {
      s.contact.model = PenaltyModel::Discrete;
    } else if (model.empty() || model == "continuous") {
      s.contact.model = PenaltyModel::Continuous;
    } else {
      r.fail("contact.model", "must be continuous or discrete (got '" + model + "')");
    }
    if (c.contains("stiffness") && c.contains("stiffness_per_area")) {
      r.fail("contact.stiffness", "and contact.stiffness_per_area are exclusive");
    }
    if (c.contains("damping") && c.contains("damping_ratio")) {
      r.fail("contact.damping", "and contact.damping_ratio are exclusive");
    }
    s.contact.stiffness = r.ranged(c, "stiffness", "contact", s.contact.stiffness, 0.0, kMaxStiffness, true);
    s.contact.damping = r.ranged(c, "damping", "contact", s.contact.damping, 0.0, kMaxDamping);
    if (c.contains("stiffness")) s.contact.stiffnessPerArea = 0.0;  // the paper's per-point law
    s.contact.stiffnessPerArea =
        r.ranged(c, "stiffness_per_area", "contact", s.contact.stiffnessPerArea, 0.0, kMaxStiffnessPerArea, true);
    if (c.contains("damping") || c.contains("damping_ratio")) s.contact.dampingFromRestitution = false;
    s.contact.dampingRatio = r.number(c, "damping_ratio", "contact", s.contact.dampingRatio);
    if (c.contains("damping_ratio") && !(s.contact.dampingRatio >= 0 && s.contact.dampingRatio <= 2)) {
      r.fail("contact.damping_ratio", "must be in [0, 2] (got " + Reader::numberText(s.contact.dampingRatio) + ")");
    }
    s.contact.friction = r.ranged(c, "friction", "contact", s.contact.friction, 0.0, kMaxFriction);
    if (c.contains("friction")) s.contact.frictionFromBodies = false;
    const std::string frictionModel = r.string(c, "friction_model", "contact");
    if (frictionModel == "regularized") {
      s.contact.frictionModel = FrictionModel::Regularized;
    } else if (frictionModel.empty() || frictionModel == "anchor") {
      s.contact.frictionModel = FrictionModel::Anchor;
    } else {
      r.fail("contact.friction_model", "must be anchor or regularized (got '" + frictionModel + "')");
    }
    const std::string timing = r.string(c, "force_timing", "contact");
    if (timing == "next_step") {
      s.contact.forceTiming = ForceTiming::NextStep;
    } else if (timing.empty() || timing == "same_step") {
      s.contact.forceTiming = ForceTiming::SameStep;
    } else {
      r.fail("contact.force_timing", "must be same_step or next_step (got '" + timing + "')");
    }
    const std::string direction = r.string(c, "direction", "contact");
    if (direction == "field_gradient") {
      s.contact.direction = PenaltyDirection::FieldGradient;
    } else if (direction == "shell_normal") {
      s.contact.direction = PenaltyDirection::ShellNormal;
    } else if (direction.empty() || direction == "blend") {
      s.contact.direction = PenaltyDirection::Blend;
    } else {
      r.fail("contact.direction", "must be blend, shell_normal or field_gradient (got '" + direction + "')");
    }
    s.contact.subintervals = r.integer(c, "subintervals", "contact", s.contact.subintervals, 1, 1000);
    s.contact.timeOfImpactClamp = r.boolean(c, "toi_clamp", "contact", s.contact.timeOfImpactClamp);
    s.contact.toiDepthCells =
        r.ranged(c, "toi_depth_cells", "contact", s.contact.toiDepthCells, 0.0, kMaxToiDepthCells);
    s.contact.useTree = r.boolean(c, "tree", "contact", s.contact.useTree);
    const std::string mode = r.string(c, "mode", "contact");
    if (mode == "solver") {
      s.contact.mode = SdfccdContactMode::Solver;
    } else if (mode == "penalty") {
      s.contact.mode = SdfccdContactMode::Penalty;
    } else if (!mode.empty()) {  // absent: SceneContact's default mode (solver)
      r.fail("contact.mode", "must be penalty or solver (got '" + mode + "')");
    }
    if (model == "discrete" && s.contact.mode == SdfccdContactMode::Solver) {
      r.fail("contact.model", mode.empty() ? "discrete applies to penalty mode only (contact.mode defaults to solver; "
                                             "set \"mode\": \"penalty\")"
                                           : "discrete applies to penalty mode only (contact.mode is solver)");
    }
    readContactSolver(r, c, s.contact);
  }
  if (root.contains("guard")) s.guard = detail::readGuard(r, root.at("guard"));
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

std::string sceneFolderName(const std::string& name) {
  constexpr std::size_t kMaxLength = 64;  // well below NAME_MAX (255) with room for suffixes
  std::string out;
  for (const char c : name.substr(0, kMaxLength)) {
    const bool safe =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
    out += safe ? c : '_';
  }
  // A leading dot would make ".", ".." or a hidden folder.
  if (!out.empty() && out.front() == '.') out.front() = '_';
  return out.empty() ? "scene" : out;
}

Scene loadScene(const std::string& path, const SceneLoadSettings& settings) {
  Scene s = parseScene(detail::readSceneText(path), path, std::filesystem::path(path).parent_path().string(), settings);
  s.path = path;
  if (s.name.empty()) s.name = std::filesystem::path(path).stem().string();
  return s;
}

}  // namespace sdfccd
