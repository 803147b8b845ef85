/// @file
/// @brief Loading haptic scenes (JSON, through the model layer's strict reader). The CSG objects' geometry and
/// sampling: haptic_csg.cpp.
#include "sdfccd/haptics/haptic_scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>

#include "scene/haptic_scene_reader.h"
#include "sdfccd/error.h"
#include "sdfccd/mesh/mass_properties.h"
#include "sdfccd/mesh/procedural_meshes.h"
#include "sdfccd/mesh/sdf_builder.h"
#include "sdfccd/model/alpha_puzzle_piece.h"
#include "sdfccd/model/detail/guard_reader.h"
#include "sdfccd/model/detail/json_reader.h"
#include "sdfccd/model/mesh_file.h"
#include "sdfccd/model/model_cache.h"
#include "sdfccd/shell/point_shell.h"

namespace sdfccd::haptics {

void resampleSceneShell(HapticScene& scene, int points) {
  if (points < 1) throw Error("shell: points must be >= 1");
  if (!scene.shellMesh) throw Error("shell: the scene keeps no mesh to resample");
  ShellSamplingSettings sampling;
  sampling.points = points;
  sampling.iterations = scene.shellIterations;
  sampling.threads = 0;
  scene.tree = std::make_shared<const PointTree>(sampleShell(*scene.shellMesh, sampling));
}

namespace {

/// A required direction, normalized. Checked before normalizing: Eigen's normalized() of a zero vector is the zero
/// vector (no NaN), so a check on the result could never fire.
Vec3 unitAxis(const Reader& r, const Json& j, const std::string& key, const std::string& where) {
  const Vec3 v = r.vec3(j, key, where, Vec3::Zero(), true);
  if (!(v.norm() > 1e-12)) r.fail(Reader::join(where, key), "must be non-zero");
  return v.normalized();
}

}  // namespace

Rigid readPose(const Reader& r, const Json& j, const std::string& where) {
  Rigid pose = Rigid::Identity();
  pose.translation() = r.vec3(j, "position", where, Vec3::Zero(), /*required=*/true);
  pose.linear() = rotationFromVector(r.vec3(j, "rotationVector", where, Vec3::Zero()));
  return pose;
}

namespace {

CsgPrimitive readPrimitive(const Reader& r, const Json& j, const std::string& where) {
  r.checkObject(j, where);
  r.checkKeys(j, {"box", "cylinder", "capsule"}, where);
  if (j.size() != 1) r.fail(where, "must hold exactly one of box, cylinder, capsule");
  CsgPrimitive p;
  if (j.contains("box")) {
    const std::string at = Reader::join(where, "box");
    const Json& b = r.object(j, "box", where);
    r.checkKeys(b, {"center", "halfExtents"}, at);
    p.kind = CsgPrimitive::Kind::Box;
    p.center = r.vec3(b, "center", at, Vec3::Zero(), true);
    p.halfExtents = r.vec3(b, "halfExtents", at, Vec3::Zero(), true);
    if (!(p.halfExtents.minCoeff() > 0.0)) r.fail(Reader::join(at, "halfExtents"), "must be > 0");
  } else if (j.contains("cylinder")) {
    const std::string at = Reader::join(where, "cylinder");
    const Json& c = r.object(j, "cylinder", where);
    r.checkKeys(c, {"center", "radius", "halfHeight", "axis"}, at);
    p.kind = CsgPrimitive::Kind::Cylinder;
    p.center = r.vec3(c, "center", at, Vec3::Zero(), true);
    p.radius = r.positive(c, "radius", at, 0.0, true);
    p.halfHeight = r.positive(c, "halfHeight", at, 0.0, true);
    if (c.contains("axis")) p.axis = unitAxis(r, c, "axis", at);  // default: y
  } else if (j.contains("capsule")) {
    const std::string at = Reader::join(where, "capsule");
    const Json& c = r.object(j, "capsule", where);
    r.checkKeys(c, {"from", "to", "radius"}, at);
    p.kind = CsgPrimitive::Kind::Capsule;
    p.center = r.vec3(c, "from", at, Vec3::Zero(), true);
    p.end = r.vec3(c, "to", at, Vec3::Zero(), true);
    p.radius = r.positive(c, "radius", at, 0.0, true);
  } else {
    r.fail(where, "must be {\"box\": ...}, {\"cylinder\": ...} or {\"capsule\": ...}");
  }
  return p;
}

/// A mesh file named by "path": loaded (loadMeshFile), centred on its box centre and scaled so that its longest
/// side is "size".
TriangleMesh sceneMesh(const Reader& r, const Json& j, const std::string& where) {
  if (!j.contains("path") || !j.at("path").is_string()) r.fail(Reader::join(where, "path"), "must be a mesh file name");
  TriangleMesh mesh = loadMeshFile(r.file(j, "path", where));
  const Box3 box = mesh.bounds();
  const double longest = box.sizes().maxCoeff();
  if (!(longest > 0.0)) r.fail(Reader::join(where, "path"), "mesh has no extent");
  const double scale = r.positive(j, "size", where, longest) / longest;
  const Vec3 centre = box.center();
  for (Vec3& v : mesh.vertices) v = (v - centre) * scale;
  return mesh;
}

/// A procedural mesh named in the scene ("procedural": "alpha-puzzle-piece"), in its own frame, scaled by
/// "scale" (model units per unit of the generator). Not centred: two pieces placed in the generator's frame
/// (e.g. interlocked, alpha_puzzle_piece.h) keep their relative pose.
TriangleMesh proceduralMesh(const Reader& r, const Json& j, const std::string& where, const std::string& key,
                            const std::string& name) {
  TriangleMesh mesh;
  if (name == "alpha-puzzle-piece") {
    mesh = makeAlphaPuzzlePiece();
  } else {
    r.fail(Reader::join(where, key), "must be \"alpha-puzzle-piece\"");
  }
  const double scale = r.positive(j, "scale", where, 1.0);
  for (Vec3& v : mesh.vertices) v *= scale;
  return mesh;
}

}  // namespace

std::shared_ptr<const SdfGrid> meshObstacleGrid(const TriangleMesh& mesh, const SdfBuildSettings& build,
                                                const std::string& cacheDir, const std::string& name) {
  constexpr int kCacheVersion = 2;  // 2: self-intersecting meshes signed by winding number
  ModelCacheKey key;
  key.add(mesh.vertices.data(), mesh.vertices.size() * sizeof(Vec3));
  key.add(mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]));
  key.add("v" + std::to_string(kCacheVersion) + " r" + std::to_string(build.resolution) + " p" +
          std::to_string(build.padding) + " s" + toString(build.signMethod));
  return ModelCache(cacheDir).field(name, key, [&] { return buildSdf(mesh, build).grid; });
}

SceneField readSceneField(const Reader& r, const Json& obstacle, const std::string& at, const std::string& cacheDir,
                          const std::vector<std::string>& extraKeys) {
  std::set<std::string> keys = {"plane", "mesh", "spacing", "paddingCells", "offsetCells", "solids", "holes"};
  keys.insert(extraKeys.begin(), extraKeys.end());
  r.checkKeys(obstacle, keys, at);
  SceneField scene;
  if (obstacle.contains("plane")) {
    const std::string where = Reader::join(at, "plane");
    const Json& p = r.object(obstacle, "plane", at);
    r.checkKeys(p, {"normal", "offset", "cellSize"}, where);
    scene.plane.emplace(unitAxis(r, p, "normal", where), r.number(p, "offset", where, 0.0));
    scene.cellSize = r.positive(p, "cellSize", where, 1e-3);
  } else if (obstacle.contains("mesh")) {
    const std::string where = Reader::join(at, "mesh");
    const Json& m = r.object(obstacle, "mesh", at);
    r.checkKeys(m, {"path", "procedural", "size", "scale", "resolution", "padding", "offsetCells"}, where);
    std::string meshName;
    TriangleMesh mesh;
    if (m.contains("procedural")) {
      if (!m.at("procedural").is_string()) r.fail(Reader::join(where, "procedural"), "must be a name");
      meshName = m.at("procedural").get<std::string>();
      mesh = proceduralMesh(r, m, where, "procedural", meshName);
    } else {
      mesh = sceneMesh(r, m, where);
      meshName = std::filesystem::path(m.at("path").get<std::string>()).stem().string();
    }
    SdfBuildSettings build;
    // Counts are read as range-checked integers, never cast from a double (a 1e12 would be undefined behaviour).
    build.resolution = r.integer(m, "resolution", where, 64, 4, 2048);
    build.padding = r.integer(m, "padding", where, 4, 0, 64);
    build.threads = 0;
    std::shared_ptr<const SdfGrid> grid = meshObstacleGrid(mesh, build, cacheDir, meshName);
    const double offsetCells = r.number(m, "offsetCells", where, 0.0);
    if (offsetCells != 0.0) {
      std::vector<float> values = grid->values();
      for (float& v : values) v = static_cast<float>(v - offsetCells * grid->spacing());
      grid = std::make_shared<const SdfGrid>(grid->nodeCounts(), grid->origin(), grid->spacing(), std::move(values));
    }
    scene.cellSize = grid->spacing();
    scene.grid = std::make_shared<const GridField>(grid);
  } else {
    CsgObstacle csg;
    csg.spacing = r.positive(obstacle, "spacing", at, 0.0, true);
    csg.paddingCells = r.integer(obstacle, "paddingCells", at, 3, 0, 1000);
    csg.offsetCells = r.number(obstacle, "offsetCells", at, 0.0);
    if (!obstacle.contains("solids") || !obstacle.at("solids").is_array() || obstacle.at("solids").empty())
      r.fail(Reader::join(at, "solids"), "must be a non-empty array");
    for (const Json& s : obstacle.at("solids")) {
      csg.solids.push_back(
          readPrimitive(r, s, Reader::join(at, "solids") + "[" + std::to_string(csg.solids.size()) + "]"));
    }
    if (obstacle.contains("holes")) {
      if (!obstacle.at("holes").is_array()) r.fail(Reader::join(at, "holes"), "must be an array");
      for (const Json& s : obstacle.at("holes")) {
        csg.holes.push_back(
            readPrimitive(r, s, Reader::join(at, "holes") + "[" + std::to_string(csg.holes.size()) + "]"));
      }
    }
    scene.grid = std::make_shared<const GridField>(sampleCsgObstacle(csg));
    scene.cellSize = csg.spacing;
  }
  return scene;
}

namespace {

void readObstacle(const Reader& r, const Json& root, const std::string& cacheDir, HapticScene& scene) {
  SceneField field = readSceneField(r, r.object(root, "obstacle", ""), "obstacle", cacheDir, {});
  scene.grid = std::move(field.grid);
  scene.plane = field.plane;
  scene.cellSize = field.cellSize;
}

}  // namespace

TriangleMesh readShellMesh(const Reader& r, const Json& shellJson, const std::string& where) {
  const std::string shape = r.string(shellJson, "shape", where);
  TriangleMesh mesh;
  if (shape == "box") {
    const Vec3 half = r.vec3(shellJson, "halfExtents", where, Vec3::Zero(), true);
    if (!(half.minCoeff() > 0.0)) r.fail(Reader::join(where, "halfExtents"), "must be > 0");
    mesh = makeBox(half);
  } else if (shape == "cylinder") {
    mesh = makeCylinder(r.positive(shellJson, "radius", where, 0.0, true),
                        r.positive(shellJson, "height", where, 0.0, true),
                        r.integer(shellJson, "segments", where, 64, 3, 4096));
  } else if (shape == "sphere") {
    mesh = makeIcosphere(r.positive(shellJson, "radius", where, 0.0, true),
                         r.integer(shellJson, "subdivisions", where, 3, 0, 7));
  } else if (shape == "mesh") {
    mesh = sceneMesh(r, shellJson, where);
  } else if (shape == "alpha-puzzle-piece") {
    mesh = proceduralMesh(r, shellJson, where, "shape", shape);
  } else if (shape == "block-with-hole") {
    mesh = blockWithHoleMesh(r, shellJson, where);
  } else {
    r.fail(Reader::join(where, "shape"), "must be box, cylinder, sphere, mesh, alpha-puzzle-piece or block-with-hole");
  }
  return mesh;
}

namespace {

/// The manipulated object: its mesh moved onto its centre of mass, mass properties and shell. Returns the centre
/// of mass in the mesh's own frame.
Vec3 readShell(const Reader& r, const Json& root, const std::string& cacheDir, HapticScene& scene) {
  const std::string where = "shell";
  const Json& shellJson = r.object(root, "shell", "");
  r.checkKeys(shellJson,
              {"shape", "halfExtents", "radius", "height", "segments", "subdivisions", "path", "size", "scale", "mass",
               "points", "iterations", "field", "holeRadius"},
              where);
  TriangleMesh mesh = readShellMesh(r, shellJson, where);
  Vec3 centerOfMassInMesh = Vec3::Zero();
  MassPropertiesSettings massSettings;
  massSettings.mass = r.positive(shellJson, "mass", where, 0.05);
  scene.mass = massSettings.mass;
  try {
    const MassProperties props = computeMassProperties(mesh, massSettings);
    // The body frame's origin is the centre of mass: move the mesh (and so the shell) onto it.
    centerOfMassInMesh = props.centerOfMassInMesh;
    for (Vec3& v : mesh.vertices) v -= props.centerOfMassInMesh;
    scene.inertiaDiagonal = props.inertiaAboutCenterOfMass.diagonal();
  } catch (const Error&) {
    // An open scanned mesh has no enclosed volume: take the solid box around it instead.
    const Vec3 e = mesh.bounds().sizes();
    scene.inertiaDiagonal =
        scene.mass / 12.0 *
        Vec3(e.y() * e.y() + e.z() * e.z(), e.x() * e.x() + e.z() * e.z(), e.x() * e.x() + e.y() * e.y());
  }
  // (Mesh axes are kept: the off-diagonal inertia of an unsymmetric mesh is dropped, an approximation of
  // the QP's metric and of the penalty object's rotational inertia.)
  ShellSamplingSettings sampling;
  sampling.points = r.integer(shellJson, "points", where, 1000, 1, 10000000);
  sampling.iterations = r.integer(shellJson, "iterations", where, 10, 0, 1000);
  sampling.threads = 1;
  scene.tree = std::make_shared<const PointTree>(sampleShell(mesh, sampling));
  scene.shellIterations = sampling.iterations;
  scene.shellMesh = std::make_shared<const TriangleMesh>(mesh);
  if (shellJson.contains("field")) scene.toolField = readToolField(r, shellJson, where, mesh, cacheDir);
  return centerOfMassInMesh;
}

void readDevice(const Reader& r, const Json& root, DeviceSettings& s) {
  if (!root.contains("device")) return;
  const std::string where = "device";
  const Json& d = r.object(root, "device", "");
  r.checkKeys(d,
              {"mass", "inertia", "linearFriction", "angularFriction", "maxForce", "maxTorque", "userStiffness",
               "userDamping", "userAngularStiffness", "userAngularDamping"},
              where);
  s.mass = r.positive(d, "mass", where, s.mass);
  s.inertiaDiagonal = Vec3::Constant(r.positive(d, "inertia", where, s.inertiaDiagonal.x()));
  s.linearFriction = r.nonNegative(d, "linearFriction", where, s.linearFriction);
  s.angularFriction = r.nonNegative(d, "angularFriction", where, s.angularFriction);
  s.maxForce = r.positive(d, "maxForce", where, s.maxForce);
  s.maxTorque = r.positive(d, "maxTorque", where, s.maxTorque);
  s.userStiffness = r.nonNegative(d, "userStiffness", where, s.userStiffness);
  s.userDamping = r.nonNegative(d, "userDamping", where, s.userDamping);
  s.userAngularStiffness = r.nonNegative(d, "userAngularStiffness", where, s.userAngularStiffness);
  s.userAngularDamping = r.nonNegative(d, "userAngularDamping", where, s.userAngularDamping);
}

/// The constraint-based renderer (tolerances in cells of `cell`).
void readConstraint(const Reader& r, const Json& root, double cell, GodObjectSettings& g) {
  g.sigma = 0.02 * cell;
  g.contactThreshold = 0.05 * cell;
  g.slideFloor = 0.01 * cell;
  g.sinkTolerance = 1e-4 * cell;
  g.maxStepTranslation = 2.0 * cell;
  if (root.contains("constraint")) {
    const std::string where = "constraint";
    const Json& c = r.object(root, "constraint", "");
    r.checkKeys(
        c,
        {"couplingGain", "renderStiffness", "sigmaCells", "contactThresholdCells", "slideFloorCells",
         "sinkToleranceCells", "maxStepCells", "maxStepRotation", "depthCorrection", "friction", "frictionFaces"},
        where);
    g.couplingGain = r.positive(c, "couplingGain", where, g.couplingGain);
    g.renderStiffness = r.nonNegative(c, "renderStiffness", where, g.renderStiffness);
    g.sigma = r.nonNegative(c, "sigmaCells", where, 0.02) * cell;
    g.contactThreshold = r.nonNegative(c, "contactThresholdCells", where, 0.05) * cell;
    g.slideFloor = r.number(c, "slideFloorCells", where, 0.01) * cell;
    g.sinkTolerance = r.nonNegative(c, "sinkToleranceCells", where, 1e-4) * cell;
    g.maxStepTranslation = r.nonNegative(c, "maxStepCells", where, 2.0) * cell;
    g.maxStepRotation = r.nonNegative(c, "maxStepRotation", where, g.maxStepRotation);
    g.depthCorrection = r.nonNegative(c, "depthCorrection", where, g.depthCorrection);
    g.qp.friction = r.nonNegative(c, "friction", where, g.qp.friction);
    g.qp.frictionFaces = r.integer(c, "frictionFaces", where, g.qp.frictionFaces, 3, 64);
  }
  if (g.couplingGain > 1.0) r.fail("constraint.couplingGain", "must be in (0, 1]");
  if (g.slideFloor > g.sigma) r.fail("constraint.slideFloorCells", "must be <= sigmaCells");
}

/// The penalty renderer (the coupling's displacement limit in cells of `cell`).
void readPenalty(const Reader& r, const Json& root, double cell, PenaltyRendererSettings& p) {
  p.coupling.maxDisplacement = 0.5 * cell;
  if (!root.contains("penalty")) return;
  const std::string where = "penalty";
  const Json& c = r.object(root, "penalty", "");
  r.checkKeys(c,
              {"stiffness", "damping", "couplingStiffness", "couplingDamping", "couplingAngularStiffness",
               "couplingAngularDamping", "maxDisplacementCells", "maxRotation"},
              where);
  p.contact.stiffness = r.positive(c, "stiffness", where, p.contact.stiffness);
  p.contact.damping = r.nonNegative(c, "damping", where, p.contact.damping);
  p.coupling.linearStiffness = r.positive(c, "couplingStiffness", where, p.coupling.linearStiffness);
  p.coupling.linearDamping = r.nonNegative(c, "couplingDamping", where, p.coupling.linearDamping);
  p.coupling.angularStiffness = r.positive(c, "couplingAngularStiffness", where, p.coupling.angularStiffness);
  p.coupling.angularDamping = r.nonNegative(c, "couplingAngularDamping", where, p.coupling.angularDamping);
  p.coupling.maxDisplacement = r.positive(c, "maxDisplacementCells", where, 0.5) * cell;
  p.coupling.maxRotation = r.positive(c, "maxRotation", where, p.coupling.maxRotation);
}

/// One check, checks.<name> = {<axisKey>: a unit vector, <levelKey>: a number}: false when the scene has none.
bool readCheck(const Reader& r, const Json& checks, const std::string& name, const std::string& axisKey,
               const std::string& levelKey, Vec3& axis, double& level) {
  if (!checks.contains(name)) return false;
  const std::string where = "checks." + name;
  const Json& c = r.object(checks, name, "checks");
  r.checkKeys(c, {axisKey, levelKey}, where);
  axis = unitAxis(r, c, axisKey, where);
  level = r.number(c, levelKey, where, 0.0, true);
  return true;
}

void readChecks(const Reader& r, const Json& root, HapticSceneChecks& checks) {
  if (!root.contains("checks")) return;
  const Json& c = r.object(root, "checks", "");
  r.checkKeys(c, {"insert", "tunnel"}, "checks");
  checks.hasInsert = readCheck(r, c, "insert", "axis", "depth", checks.insertAxis, checks.insertDepth);
  checks.hasTunnel = readCheck(r, c, "tunnel", "normal", "offset", checks.tunnelNormal, checks.tunnelOffset);
}

}  // namespace

HapticScene loadHapticScene(const std::string& path, const HapticSceneLoadSettings& loadSettings) {
  const Reader r(path, detail::SceneFileSearch{std::filesystem::path(path).parent_path().string(), {}, true});
  const Json root = r.parseObject(detail::readSceneText(path));
  r.checkKeys(root,
              {"name", "description", "obstacle", "obstacles", "shell", "poseFrame", "start", "script", "seconds",
               "device", "constraint", "penalty", "checks", "guard"},
              "");
  HapticScene scene;
  scene.name = root.contains("name") ? r.string(root, "name", "") : "unnamed";
  scene.description = r.string(root, "description", "");

  if (root.contains("obstacle") == root.contains("obstacles"))
    r.fail("obstacles", "give either \"obstacle\" (one static field) or \"obstacles\" (a list)");
  const Vec3 centerOfMassInMesh = readShell(r, root, loadSettings.cacheDir, scene);
  if (root.contains("obstacle")) {
    readObstacle(r, root, loadSettings.cacheDir, scene);
  } else {
    readObstacles(r, root, loadSettings.cacheDir, scene);
  }
  // Poses in the file place the body's centre of mass ("poseFrame": "body", the default) or the shell mesh's own
  // frame before centring ("mesh": e.g. a procedural piece placed in its generator's frame).
  const std::string poseFrame = root.contains("poseFrame") ? r.string(root, "poseFrame", "") : "body";
  if (poseFrame != "body" && poseFrame != "mesh") r.fail("poseFrame", "must be \"body\" or \"mesh\"");
  Rigid meshFromBody = Rigid::Identity();
  if (poseFrame == "mesh") meshFromBody.translation() = centerOfMassInMesh;
  const Json& start = r.object(root, "start", "");
  r.checkKeys(start, {"position", "rotationVector"}, "start");
  scene.worldFromBodyStart = readPose(r, start, "start") * meshFromBody;

  // Scripted user.
  if (!root.contains("script") || !root.at("script").is_array() || root.at("script").empty())
    r.fail("script", "must be a non-empty array of keyframes");
  std::vector<PoseKeyframe> keys;
  for (const Json& k : root.at("script")) {
    const std::string where = "script[" + std::to_string(keys.size()) + "]";
    r.checkObject(k, where);
    r.checkKeys(k, {"t", "position", "rotationVector"}, where);
    (void)r.number(k, "t", where, 0.0, /*required=*/true);
    keys.push_back({r.ranged(k, "t", where, 0.0, 0.0, 3600.0), readPose(r, k, where) * meshFromBody});
  }
  try {
    scene.script = UserScript(std::move(keys));
  } catch (const Error& e) {  // the script's own checks (increasing times), with the scene and key named
    r.fail("script", std::string("is invalid: ") + e.what());
  }
  scene.seconds = r.ranged(root, "seconds", "", scene.script.duration() + 0.5, 0.0, 3600.0, /*lowOpen=*/true);

  readDevice(r, root, scene.device);
  scene.god.mass = scene.mass;
  scene.god.inertiaDiagonal = scene.inertiaDiagonal;
  readConstraint(r, root, scene.cellSize, scene.god);
  scene.penalty.mass = scene.mass;
  scene.penalty.inertiaDiagonal = scene.inertiaDiagonal;
  scene.penalty.timestep = 1.0 / scene.device.rateHz;
  readPenalty(r, root, scene.cellSize, scene.penalty);
  readChecks(r, root, scene.checks);
  if (root.contains("guard")) scene.guard = detail::readGuard(r, r.object(root, "guard", ""));
  return scene;
}

}  // namespace sdfccd::haptics
