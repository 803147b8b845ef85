/// @file
/// @brief The scene reader: parseScene and loadScene (scene.h), on the shared strict-JSON helpers
/// (detail/json_reader.h).
#include <cmath>
#include <filesystem>

#include "sdfccd/error.h"
#include "sdfccd/model/detail/json_reader.h"
#include "sdfccd/model/scene.h"

namespace sdfccd {
namespace {

using detail::Json;
using Reader = detail::JsonReader;

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
  b.scale = r.number(j, "scale", where, 1.0);
  if (!(b.scale > 0)) r.fail(Reader::join(where, "scale"), "must be > 0 (got " + Reader::numberText(b.scale) + ")");
  b.mass = r.number(j, "mass", where, 1.0, !b.isStatic && !b.kinematic);
  if (!b.isStatic && !b.kinematic && !(b.mass > 0))
    r.fail(Reader::join(where, "mass"), "must be > 0 (got " + Reader::numberText(b.mass) + ")");
  b.position = r.vec3(j, "position", where, Vec3::Zero());
  if (j.contains("orientation")) b.orientation = r.unitQuaternion(j, "orientation", where);
  b.velocity = r.vec3(j, "velocity", where, Vec3::Zero());
  b.angularVelocity = r.vec3(j, "angular_velocity", where, Vec3::Zero());
  b.friction = r.number(j, "friction", where, b.friction);
  if (!(b.friction >= 0) || !std::isfinite(b.friction)) {
    r.fail(Reader::join(where, "friction"), "must be finite and >= 0 (got " + Reader::numberText(b.friction) + ")");
  }
  b.restitution = r.number(j, "restitution", where, b.restitution);
  if (!(b.restitution >= 0) || !std::isfinite(b.restitution)) {
    r.fail(Reader::join(where, "restitution"),
           "must be finite and >= 0 (got " + Reader::numberText(b.restitution) + ")");
  }
  b.points = r.integer(j, "points", where, 0, 0, 10000000);
  b.pointsGiven = j.contains("points");
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

Scene parseScene(const std::string& text, const std::string& name, const std::string& baseDir,
                 const SceneLoadSettings& settings) {
  const Reader r(name, detail::SceneFileSearch{baseDir, settings.searchFolders, settings.requireFiles});
  const Json root = r.parseObject(text);
  r.checkKeys(root,
              {"name", "description", "timestep", "frames", "gravity", "effects", "ground", "contact", "bodies",
               "sleeping", "camera"},
              "");
  Scene s;
  s.name = r.string(root, "name", "");
  (void)r.string(root, "description", "");
  s.timestep = r.number(root, "timestep", "", s.timestep);
  if (!(s.timestep > 0) || s.timestep > 1.0)
    r.fail("timestep", "must be in (0, 1] s (got " + Reader::numberText(s.timestep) + ")");
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
                 "subintervals", "toi_clamp", "toi_depth_cells", "tree", "force_timing", "direction", "mode"},
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
    s.contact.stiffness = r.number(c, "stiffness", "contact", s.contact.stiffness);
    s.contact.damping = r.number(c, "damping", "contact", s.contact.damping);
    if (!(s.contact.stiffness > 0)) r.fail("contact.stiffness", "must be > 0");
    if (!(s.contact.damping >= 0)) r.fail("contact.damping", "must be >= 0");
    if (c.contains("stiffness")) s.contact.stiffnessPerArea = 0.0;  // the paper's per-point law
    s.contact.stiffnessPerArea = r.number(c, "stiffness_per_area", "contact", s.contact.stiffnessPerArea);
    if (c.contains("stiffness_per_area") && !(s.contact.stiffnessPerArea > 0)) {
      r.fail("contact.stiffness_per_area", "must be > 0 (got " + Reader::numberText(s.contact.stiffnessPerArea) + ")");
    }
    if (c.contains("damping") || c.contains("damping_ratio")) s.contact.dampingFromRestitution = false;
    s.contact.dampingRatio = r.number(c, "damping_ratio", "contact", s.contact.dampingRatio);
    if (c.contains("damping_ratio") && !(s.contact.dampingRatio >= 0 && s.contact.dampingRatio <= 2)) {
      r.fail("contact.damping_ratio", "must be in [0, 2] (got " + Reader::numberText(s.contact.dampingRatio) + ")");
    }
    s.contact.friction = r.number(c, "friction", "contact", s.contact.friction);
    if (!(s.contact.friction >= 0)) r.fail("contact.friction", "must be >= 0");
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
    s.contact.toiDepthCells = r.number(c, "toi_depth_cells", "contact", s.contact.toiDepthCells);
    if (!(s.contact.toiDepthCells >= 0)) r.fail("contact.toi_depth_cells", "must be >= 0");
    s.contact.useTree = r.boolean(c, "tree", "contact", s.contact.useTree);
    const std::string mode = r.string(c, "mode", "contact");
    if (mode == "solver") {
      s.contact.mode = SdfccdContactMode::Solver;
    } else if (mode == "penalty") {
      s.contact.mode = SdfccdContactMode::Penalty;
    } else if (!mode.empty()) {
      r.fail("contact.mode", "must be penalty or solver (got '" + mode + "')");
    }  // no "mode": SceneContact's default (solver)
    if (model == "discrete" && s.contact.mode == SdfccdContactMode::Solver) {
      r.fail("contact.model", mode.empty() ? "discrete needs \"mode\": \"penalty\" (contact.mode defaults to solver)"
                                           : "applies to penalty mode only (contact.mode is solver)");
    }
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

Scene loadScene(const std::string& path, const SceneLoadSettings& settings) {
  Scene s = parseScene(detail::readSceneText(path), path, std::filesystem::path(path).parent_path().string(), settings);
  s.path = path;
  if (s.name.empty()) s.name = std::filesystem::path(path).stem().string();
  return s;
}

}  // namespace sdfccd
