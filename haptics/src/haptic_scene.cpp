/// @file
/// @brief Loading haptic scenes (JSON, through the model layer's strict reader) and sampling their CSG static
/// objects on a grid.
#include "sdfccd/haptics/haptic_scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

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

using detail::Json;
using Reader = detail::JsonReader;

double CsgPrimitive::signedDistance(const Vec3& p) const {
  if (kind == Kind::Box) {
    const Vec3 q = (p - center).cwiseAbs() - halfExtents;
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
  }
  const Vec3 d3 = p - center;
  const double radial = std::hypot(d3.x(), d3.z()) - halfExtents.x();
  const double axial = std::abs(d3.y()) - halfExtents.y();
  return std::min(std::max(radial, axial), 0.0) + std::hypot(std::max(radial, 0.0), std::max(axial, 0.0));
}

double CsgObstacle::signedDistance(const Vec3& p) const {
  double solid = 1e300;
  for (const CsgPrimitive& s : solids) solid = std::min(solid, s.signedDistance(p));
  double hole = 1e300;
  for (const CsgPrimitive& h : holes) hole = std::min(hole, h.signedDistance(p));
  return holes.empty() ? solid : std::max(solid, -hole);
}

std::shared_ptr<const SdfGrid> sampleCsgObstacle(const CsgObstacle& obstacle) {
  if (obstacle.solids.empty()) throw Error("obstacle: no solids");
  if (!(obstacle.spacing > 0.0) || !std::isfinite(obstacle.spacing)) throw Error("obstacle: spacing must be > 0");
  if (obstacle.paddingCells < 0 || obstacle.paddingCells > 1000) throw Error("obstacle: paddingCells out of range");
  if (!std::isfinite(obstacle.offsetCells)) throw Error("obstacle: offsetCells is not finite");
  Box3 box;
  for (const CsgPrimitive& s : obstacle.solids) {
    const Vec3 half = s.kind == CsgPrimitive::Kind::Box ? s.halfExtents
                                                        : Vec3(s.halfExtents.x(), s.halfExtents.y(), s.halfExtents.x());
    if (!s.center.allFinite() || !half.allFinite() || !(half.minCoeff() > 0.0))
      throw Error("obstacle: a solid has a non-positive or non-finite size");
    box.extend(s.center - half);
    box.extend(s.center + half);
  }
  const double h = obstacle.spacing;
  const Vec3 origin = box.min() - Vec3::Constant(obstacle.paddingCells * h);
  const Vec3 size = box.sizes() + Vec3::Constant(2.0 * obstacle.paddingCells * h);
  Vec3i nodes;
  double total = 1.0;
  double perAxis[3];
  for (int a = 0; a < 3; ++a) {
    perAxis[a] = std::ceil(size[a] / h - 1e-9) + 1.0;  // a double: checked before any cast to int
    total *= perAxis[a];
  }
  if (!(total <= 64.0 * 1024 * 1024)) throw Error("obstacle: grid too large (over 64 M nodes); raise the spacing");
  for (int a = 0; a < 3; ++a) nodes[a] = static_cast<int>(perAxis[a]);
  std::vector<float> values(static_cast<std::size_t>(total));
  const double offset = obstacle.offsetCells * h;
  std::size_t n = 0;
  for (int k = 0; k < nodes.z(); ++k)
    for (int j = 0; j < nodes.y(); ++j)
      for (int i = 0; i < nodes.x(); ++i)
        values[n++] = static_cast<float>(obstacle.signedDistance(origin + h * Vec3(i, j, k)) - offset);
  return std::make_shared<const SdfGrid>(nodes, origin, h, std::move(values));
}

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

Rigid readPose(const Reader& r, const Json& j, const std::string& where) {
  Rigid pose = Rigid::Identity();
  pose.translation() = r.vec3(j, "position", where, Vec3::Zero(), /*required=*/true);
  pose.linear() = rotationFromVector(r.vec3(j, "rotationVector", where, Vec3::Zero()));
  return pose;
}

CsgPrimitive readPrimitive(const Reader& r, const Json& j, const std::string& where) {
  r.checkObject(j, where);
  r.checkKeys(j, {"box", "cylinder"}, where);
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
    r.checkKeys(c, {"center", "radius", "halfHeight"}, at);
    p.kind = CsgPrimitive::Kind::CylinderY;
    p.center = r.vec3(c, "center", at, Vec3::Zero(), true);
    p.halfExtents = Vec3(r.positive(c, "radius", at, 0.0, true), r.positive(c, "halfHeight", at, 0.0, true), 0.0);
  } else {
    r.fail(where, "must be {\"box\": ...} or {\"cylinder\": ...}");
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

/// The exact field of a mesh obstacle: buildSdf, or the model cache's copy keyed by the mesh's vertices and
/// triangles and the build parameters.
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

void readObstacle(const Reader& r, const Json& root, const std::string& cacheDir, HapticScene& scene) {
  const Json& obstacle = r.object(root, "obstacle", "");
  r.checkKeys(obstacle, {"plane", "mesh", "spacing", "paddingCells", "offsetCells", "solids", "holes"}, "obstacle");
  if (obstacle.contains("plane")) {
    const std::string where = "obstacle.plane";
    const Json& p = r.object(obstacle, "plane", "obstacle");
    r.checkKeys(p, {"normal", "offset", "cellSize"}, where);
    scene.plane.emplace(unitAxis(r, p, "normal", where), r.number(p, "offset", where, 0.0));
    scene.cellSize = r.positive(p, "cellSize", where, 1e-3);
  } else if (obstacle.contains("mesh")) {
    const std::string where = "obstacle.mesh";
    const Json& m = r.object(obstacle, "mesh", "obstacle");
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
    csg.spacing = r.positive(obstacle, "spacing", "obstacle", 0.0, true);
    csg.paddingCells = r.integer(obstacle, "paddingCells", "obstacle", 3, 0, 1000);
    csg.offsetCells = r.number(obstacle, "offsetCells", "obstacle", 0.0);
    if (!obstacle.contains("solids") || !obstacle.at("solids").is_array() || obstacle.at("solids").empty())
      r.fail("obstacle.solids", "must be a non-empty array");
    for (const Json& s : obstacle.at("solids")) {
      csg.solids.push_back(readPrimitive(r, s, "obstacle.solids[" + std::to_string(csg.solids.size()) + "]"));
    }
    if (obstacle.contains("holes")) {
      if (!obstacle.at("holes").is_array()) r.fail("obstacle.holes", "must be an array");
      for (const Json& s : obstacle.at("holes")) {
        csg.holes.push_back(readPrimitive(r, s, "obstacle.holes[" + std::to_string(csg.holes.size()) + "]"));
      }
    }
    scene.grid = std::make_shared<const GridField>(sampleCsgObstacle(csg));
    scene.cellSize = csg.spacing;
  }
}

/// The manipulated object: its mesh moved onto its centre of mass, mass properties and shell. Returns the centre
/// of mass in the mesh's own frame.
Vec3 readShell(const Reader& r, const Json& root, HapticScene& scene) {
  const std::string where = "shell";
  const Json& shellJson = r.object(root, "shell", "");
  r.checkKeys(shellJson,
              {"shape", "halfExtents", "radius", "height", "segments", "subdivisions", "path", "size", "scale", "mass",
               "points", "iterations"},
              where);
  const std::string shape = r.string(shellJson, "shape", where);
  TriangleMesh mesh;
  if (shape == "box") {
    const Vec3 half = r.vec3(shellJson, "halfExtents", where, Vec3::Zero(), true);
    if (!(half.minCoeff() > 0.0)) r.fail("shell.halfExtents", "must be > 0");
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
  } else {
    r.fail("shell.shape", "must be box, cylinder, sphere, mesh or alpha-puzzle-piece");
  }
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
    r.checkKeys(c,
                {"couplingGain", "renderStiffness", "sigmaCells", "contactThresholdCells", "slideFloorCells",
                 "sinkToleranceCells", "maxStepCells", "maxStepRotation", "depthCorrection", "friction",
                 "frictionFaces"},
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

void readChecks(const Reader& r, const Json& root, HapticSceneChecks& checks) {
  if (!root.contains("checks")) return;
  const Json& c = r.object(root, "checks", "");
  r.checkKeys(c, {"insert", "tunnel"}, "checks");
  if (c.contains("insert")) {
    const std::string where = "checks.insert";
    const Json& i = r.object(c, "insert", "checks");
    r.checkKeys(i, {"axis", "depth"}, where);
    checks.hasInsert = true;
    checks.insertAxis = unitAxis(r, i, "axis", where);
    checks.insertDepth = r.number(i, "depth", where, 0.0, true);
  }
  if (c.contains("tunnel")) {
    const std::string where = "checks.tunnel";
    const Json& t = r.object(c, "tunnel", "checks");
    r.checkKeys(t, {"normal", "offset"}, where);
    checks.hasTunnel = true;
    checks.tunnelNormal = unitAxis(r, t, "normal", where);
    checks.tunnelOffset = r.number(t, "offset", where, 0.0, true);
  }
}

}  // namespace

HapticScene loadHapticScene(const std::string& path, const HapticSceneLoadSettings& loadSettings) {
  const Reader r(path, detail::SceneFileSearch{std::filesystem::path(path).parent_path().string(), {}, true});
  const Json root = r.parseObject(detail::readSceneText(path));
  r.checkKeys(root,
              {"name", "description", "obstacle", "shell", "poseFrame", "start", "script", "seconds", "device",
               "constraint", "penalty", "checks", "guard"},
              "");
  HapticScene scene;
  scene.name = root.contains("name") ? r.string(root, "name", "") : "unnamed";
  scene.description = r.string(root, "description", "");

  readObstacle(r, root, loadSettings.cacheDir, scene);
  const Vec3 centerOfMassInMesh = readShell(r, root, scene);
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
