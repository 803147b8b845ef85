/// @file
/// @brief Loading haptic scenes (JSON) and sampling their CSG static objects on a grid.
#include "sdfccd/haptics/haptic_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "sdfccd/model/alpha_puzzle_piece.h"
#include "sdfccd/error.h"
#include "sdfccd/mesh/mass_properties.h"
#include "sdfccd/shell/point_shell.h"
#include "sdfccd/mesh/procedural_meshes.h"
#include "sdfccd/mesh/sdf_builder.h"
#include "sdfccd/field/sdf_file.h"

namespace sdfccd::haptics {

using Json = nlohmann::json;

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
  for (int a = 0; a < 3; ++a) {
    nodes[a] = static_cast<int>(std::ceil(size[a] / h - 1e-9)) + 1;
    total *= nodes[a];
  }
  if (total > 64.0 * 1024 * 1024) throw Error("obstacle: grid too large (over 64 M nodes); raise the spacing");
  std::vector<float> values(static_cast<std::size_t>(total));
  const double offset = obstacle.offsetCells * h;
  std::size_t n = 0;
  for (int k = 0; k < nodes.z(); ++k)
    for (int j = 0; j < nodes.y(); ++j)
      for (int i = 0; i < nodes.x(); ++i)
        values[n++] = static_cast<float>(obstacle.signedDistance(origin + h * Vec3(i, j, k)) - offset);
  return std::make_shared<const SdfGrid>(nodes, origin, h, std::move(values));
}

namespace {

struct Reader {
  std::string file;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw Error(file + ": '" + key + "' " + what);
  }
  double number(const Json& j, const std::string& key) const {
    if (!j.contains(key)) fail(key, "is missing");
    if (!j.at(key).is_number()) fail(key, "must be a number");
    const double v = j.at(key).get<double>();
    if (!std::isfinite(v)) fail(key, "must be finite");
    return v;
  }
  double number(const Json& j, const std::string& key, double fallback) const {
    return j.contains(key) ? number(j, key) : fallback;
  }
  double positive(const Json& j, const std::string& key, double fallback) const {
    const double v = number(j, key, fallback);
    if (!(v > 0.0)) fail(key, "must be > 0");
    return v;
  }
  double nonNegative(const Json& j, const std::string& key, double fallback) const {
    const double v = number(j, key, fallback);
    if (!(v >= 0.0)) fail(key, "must be >= 0");
    return v;
  }
  Vec3 vec3(const Json& j, const std::string& key) const {
    if (!j.contains(key)) fail(key, "is missing");
    const Json& a = j.at(key);
    if (!a.is_array() || a.size() != 3) fail(key, "must be an array of 3 numbers");
    Vec3 v;
    for (int i = 0; i < 3; ++i) {
      if (!a[static_cast<std::size_t>(i)].is_number()) fail(key, "must be an array of 3 numbers");
      v[i] = a[static_cast<std::size_t>(i)].get<double>();
    }
    if (!v.allFinite()) fail(key, "must be finite");
    return v;
  }
  Vec3 vec3(const Json& j, const std::string& key, const Vec3& fallback) const {
    return j.contains(key) ? vec3(j, key) : fallback;
  }
  Rigid pose(const Json& j) const {
    Rigid r = Rigid::Identity();
    r.translation() = vec3(j, "position");
    r.linear() = rotationFromVector(vec3(j, "rotationVector", Vec3::Zero()));
    return r;
  }
  const Json& object(const Json& j, const std::string& key) const {
    if (!j.contains(key)) fail(key, "is missing");
    if (!j.at(key).is_object()) fail(key, "must be an object");
    return j.at(key);
  }
  CsgPrimitive primitive(const Json& j) const {
    CsgPrimitive p;
    if (j.contains("box")) {
      const Json& b = object(j, "box");
      p.kind = CsgPrimitive::Kind::Box;
      p.center = vec3(b, "center");
      p.halfExtents = vec3(b, "halfExtents");
      if (!(p.halfExtents.minCoeff() > 0.0)) fail("halfExtents", "must be > 0");
    } else if (j.contains("cylinder")) {
      const Json& c = object(j, "cylinder");
      p.kind = CsgPrimitive::Kind::CylinderY;
      p.center = vec3(c, "center");
      p.halfExtents = Vec3(positive(c, "radius", -1.0), positive(c, "halfHeight", -1.0), 0.0);
    } else {
      fail("solids/holes", "entries must be {\"box\": ...} or {\"cylinder\": ...}");
    }
    return p;
  }
};

}  // namespace

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

/// A mesh from the scene: loaded, centred on its box centre and scaled so that its longest side is `size`.
TriangleMesh sceneMesh(const Reader& r, const Json& j, const std::string& sceneFile, const MeshLoader& loader) {
  if (!j.contains("path") || !j.at("path").is_string()) r.fail("path", "must be a mesh file name");
  if (!loader) r.fail("path", "needs a mesh loader (this build has no mesh reader)");
  const std::filesystem::path file = std::filesystem::path(sceneFile).parent_path() / j.at("path").get<std::string>();
  TriangleMesh mesh = loader(file.string());
  const Box3 box = mesh.bounds();
  const double longest = box.sizes().maxCoeff();
  if (!(longest > 0.0)) r.fail("path", "mesh has no extent");
  const double scale = r.positive(j, "size", longest) / longest;
  const Vec3 centre = box.center();
  for (Vec3& v : mesh.vertices) v = (v - centre) * scale;
  return mesh;
}

/// A procedural mesh named in the scene ("procedural": "alpha-puzzle-piece"), in its own frame, scaled by
/// `scale` (model units per unit of the generator). Not centred: two pieces placed in the generator's frame
/// (e.g. interlocked, alpha_puzzle_piece.h) keep their relative pose.
TriangleMesh proceduralMesh(const Reader& r, const Json& j, const std::string& name) {
  TriangleMesh mesh;
  if (name == "alpha-puzzle-piece") {
    mesh = makeAlphaPuzzlePiece();
  } else {
    r.fail("procedural", "must be \"alpha-puzzle-piece\"");
  }
  const double scale = r.positive(j, "scale", 1.0);
  for (Vec3& v : mesh.vertices) v *= scale;
  return mesh;
}

// FNV-1a, 64 bits: a cache key stable across compilers and runs (std::hash promises neither).
std::uint64_t fnv1a64(const void* data, std::size_t size, std::uint64_t hash = 1469598103934665603ull) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 1099511628211ull;
  }
  return hash;
}

/// The exact field of a mesh obstacle: buildSdf, or the cached copy in cacheDir keyed by the mesh's vertices and
/// triangles and the build parameters. A cache entry that fails to load is rebuilt and overwritten; a cache
/// that cannot be written is skipped silently (the field is still returned).
std::shared_ptr<const SdfGrid> meshObstacleGrid(const TriangleMesh& mesh, const SdfBuildSettings& build,
                                                const std::string& cacheDir, const std::string& name) {
  if (cacheDir.empty()) return buildSdf(mesh, build).grid;
  constexpr int kCacheVersion = 1;
  std::uint64_t key = fnv1a64(mesh.vertices.data(), mesh.vertices.size() * sizeof(Vec3));
  key = fnv1a64(mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]), key);
  const std::string parameters = "v" + std::to_string(kCacheVersion) + " r" + std::to_string(build.resolution) + " p" +
                                 std::to_string(build.padding) + " s" + toString(build.signMethod);
  key = fnv1a64(parameters.data(), parameters.size(), key);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(key));
  const std::filesystem::path file = std::filesystem::path(cacheDir) / (name + "-" + hex + ".sdf");
  std::error_code ec;
  if (std::filesystem::exists(file, ec)) {
    try {
      return std::make_shared<const SdfGrid>(loadSdf(file.string()));
    } catch (const Error&) {
      // Damaged: rebuilt and overwritten below.
    }
  }
  std::shared_ptr<const SdfGrid> grid = buildSdf(mesh, build).grid;
  std::filesystem::create_directories(cacheDir, ec);
  try {
    saveSdf(file.string(), *grid, SdfFileFormat::Native);
  } catch (const Error&) {
    // A read-only or full disk only costs the next run the build.
  }
  return grid;
}

}  // namespace

HapticScene loadHapticScene(const std::string& path, const HapticSceneLoadSettings& loadSettings) {
  const MeshLoader& meshLoader = loadSettings.meshLoader;
  std::ifstream in(path);
  if (!in) throw Error("cannot open scene '" + path + "'");
  Json root;
  try {
    root = Json::parse(in);
  } catch (const Json::exception& e) {
    throw Error(path + ": invalid JSON (" + std::string(e.what()) + ")");
  }
  if (!root.is_object()) throw Error(path + ": the scene must be a JSON object");
  const Reader r{path};
  HapticScene scene;
  scene.name = root.value("name", std::string("unnamed"));
  scene.description = root.value("description", std::string());

  // Static object.
  const Json& obstacle = r.object(root, "obstacle");
  if (obstacle.contains("plane")) {
    const Json& p = r.object(obstacle, "plane");
    scene.plane.emplace(r.vec3(p, "normal"), r.number(p, "offset", 0.0));
    scene.cellSize = r.positive(p, "cellSize", 1e-3);
  } else if (obstacle.contains("mesh")) {
    const Json& m = r.object(obstacle, "mesh");
    std::string meshName;
    TriangleMesh mesh;
    if (m.contains("procedural")) {
      if (!m.at("procedural").is_string()) r.fail("procedural", "must be a name");
      meshName = m.at("procedural").get<std::string>();
      mesh = proceduralMesh(r, m, meshName);
    } else {
      mesh = sceneMesh(r, m, path, meshLoader);
      meshName = std::filesystem::path(m.at("path").get<std::string>()).stem().string();
    }
    SdfBuildSettings build;
    build.resolution = static_cast<int>(r.positive(m, "resolution", 64));
    build.padding = static_cast<int>(r.nonNegative(m, "padding", 4));
    build.threads = 0;
    std::shared_ptr<const SdfGrid> grid = meshObstacleGrid(mesh, build, loadSettings.cacheDir, meshName);
    const double offsetCells = r.number(m, "offsetCells", 0.0);
    if (offsetCells != 0.0) {
      std::vector<float> values = grid->values();
      for (float& v : values) v = static_cast<float>(v - offsetCells * grid->spacing());
      grid = std::make_shared<const SdfGrid>(grid->nodeCounts(), grid->origin(), grid->spacing(), std::move(values));
    }
    scene.cellSize = grid->spacing();
    scene.grid = std::make_shared<const GridField>(grid);
  } else {
    CsgObstacle csg;
    csg.spacing = r.positive(obstacle, "spacing", -1.0);
    csg.paddingCells = static_cast<int>(r.nonNegative(obstacle, "paddingCells", 3));
    csg.offsetCells = r.number(obstacle, "offsetCells", 0.0);
    if (!obstacle.contains("solids") || !obstacle.at("solids").is_array() || obstacle.at("solids").empty())
      r.fail("solids", "must be a non-empty array");
    for (const Json& s : obstacle.at("solids")) csg.solids.push_back(r.primitive(s));
    if (obstacle.contains("holes")) {
      if (!obstacle.at("holes").is_array()) r.fail("holes", "must be an array");
      for (const Json& s : obstacle.at("holes")) csg.holes.push_back(r.primitive(s));
    }
    scene.grid = std::make_shared<const GridField>(sampleCsgObstacle(csg));
    scene.cellSize = csg.spacing;
  }
  const double cell = scene.cellSize;

  // Manipulated object.
  const Json& shellJson = r.object(root, "shell");
  const std::string shape = shellJson.value("shape", std::string());
  TriangleMesh mesh;
  if (shape == "box") {
    const Vec3 half = r.vec3(shellJson, "halfExtents");
    if (!(half.minCoeff() > 0.0)) r.fail("halfExtents", "must be > 0");
    mesh = makeBox(half);
  } else if (shape == "cylinder") {
    mesh = makeCylinder(r.positive(shellJson, "radius", -1.0), r.positive(shellJson, "height", -1.0),
                        static_cast<int>(r.positive(shellJson, "segments", 64)));
  } else if (shape == "sphere") {
    mesh = makeIcosphere(r.positive(shellJson, "radius", -1.0),
                         static_cast<int>(r.nonNegative(shellJson, "subdivisions", 3)));
  } else if (shape == "mesh") {
    mesh = sceneMesh(r, shellJson, path, meshLoader);
  } else if (shape == "alpha-puzzle-piece") {
    mesh = proceduralMesh(r, shellJson, shape);
  } else {
    r.fail("shell.shape", "must be box, cylinder, sphere, mesh or alpha-puzzle-piece");
  }
  Vec3 centerOfMassInMesh = Vec3::Zero();
  MassPropertiesSettings massSettings;
  massSettings.mass = r.positive(shellJson, "mass", 0.05);
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
  sampling.points = static_cast<int>(r.positive(shellJson, "points", 1000));
  sampling.iterations = static_cast<int>(r.nonNegative(shellJson, "iterations", 10));
  sampling.threads = 1;
  scene.tree = std::make_shared<const PointTree>(sampleShell(mesh, sampling));
  scene.shellIterations = sampling.iterations;
  scene.shellMesh = std::make_shared<const TriangleMesh>(mesh);
  // Poses in the file place the body's centre of mass ("poseFrame": "body", the default) or the shell mesh's own
  // frame before centring ("mesh": e.g. a procedural piece placed in its generator's frame).
  const std::string poseFrame = root.value("poseFrame", std::string("body"));
  if (poseFrame != "body" && poseFrame != "mesh") r.fail("poseFrame", "must be \"body\" or \"mesh\"");
  Rigid meshFromBody = Rigid::Identity();
  if (poseFrame == "mesh") meshFromBody.translation() = centerOfMassInMesh;
  scene.worldFromBodyStart = r.pose(r.object(root, "start")) * meshFromBody;

  // Scripted user.
  if (!root.contains("script") || !root.at("script").is_array() || root.at("script").empty())
    r.fail("script", "must be a non-empty array of keyframes");
  std::vector<PoseKeyframe> keys;
  for (const Json& k : root.at("script")) keys.push_back({r.number(k, "t"), r.pose(k) * meshFromBody});
  scene.script = UserScript(std::move(keys));
  scene.seconds = r.positive(root, "seconds", scene.script.duration() + 0.5);

  // Device.
  if (root.contains("device")) {
    const Json& d = r.object(root, "device");
    DeviceSettings& s = scene.device;
    s.mass = r.positive(d, "mass", s.mass);
    s.inertiaDiagonal = Vec3::Constant(r.positive(d, "inertia", s.inertiaDiagonal.x()));
    s.linearFriction = r.nonNegative(d, "linearFriction", s.linearFriction);
    s.angularFriction = r.nonNegative(d, "angularFriction", s.angularFriction);
    s.maxForce = r.positive(d, "maxForce", s.maxForce);
    s.maxTorque = r.positive(d, "maxTorque", s.maxTorque);
    s.userStiffness = r.nonNegative(d, "userStiffness", s.userStiffness);
    s.userDamping = r.nonNegative(d, "userDamping", s.userDamping);
    s.userAngularStiffness = r.nonNegative(d, "userAngularStiffness", s.userAngularStiffness);
    s.userAngularDamping = r.nonNegative(d, "userAngularDamping", s.userAngularDamping);
  }

  // Constraint-based renderer (tolerances in cells).
  GodObjectSettings& g = scene.god;
  g.mass = scene.mass;
  g.inertiaDiagonal = scene.inertiaDiagonal;
  g.sigma = 0.02 * cell;
  g.contactThreshold = 0.05 * cell;
  g.slideFloor = 0.01 * cell;
  g.sinkTolerance = 1e-4 * cell;
  g.maxStepTranslation = 2.0 * cell;
  if (root.contains("constraint")) {
    const Json& c = r.object(root, "constraint");
    g.couplingGain = r.positive(c, "couplingGain", g.couplingGain);
    g.renderStiffness = r.nonNegative(c, "renderStiffness", g.renderStiffness);
    g.sigma = r.nonNegative(c, "sigmaCells", 0.02) * cell;
    g.contactThreshold = r.nonNegative(c, "contactThresholdCells", 0.05) * cell;
    g.slideFloor = r.number(c, "slideFloorCells", 0.01) * cell;
    g.sinkTolerance = r.nonNegative(c, "sinkToleranceCells", 1e-4) * cell;
    g.maxStepTranslation = r.nonNegative(c, "maxStepCells", 2.0) * cell;
    g.maxStepRotation = r.nonNegative(c, "maxStepRotation", g.maxStepRotation);
    g.depthCorrection = r.nonNegative(c, "depthCorrection", g.depthCorrection);
  }
  if (g.couplingGain > 1.0) r.fail("couplingGain", "must be in (0, 1]");
  if (g.slideFloor > g.sigma) r.fail("slideFloorCells", "must be <= sigmaCells");

  // Penalty renderer.
  PenaltyRendererSettings& p = scene.penalty;
  p.mass = scene.mass;
  p.inertiaDiagonal = scene.inertiaDiagonal;
  p.timestep = 1.0 / scene.device.rateHz;
  p.coupling.maxDisplacement = 0.5 * cell;
  if (root.contains("penalty")) {
    const Json& c = r.object(root, "penalty");
    p.contact.stiffness = r.positive(c, "stiffness", p.contact.stiffness);
    p.contact.damping = r.nonNegative(c, "damping", p.contact.damping);
    p.coupling.linearStiffness = r.positive(c, "couplingStiffness", p.coupling.linearStiffness);
    p.coupling.linearDamping = r.nonNegative(c, "couplingDamping", p.coupling.linearDamping);
    p.coupling.angularStiffness = r.positive(c, "couplingAngularStiffness", p.coupling.angularStiffness);
    p.coupling.angularDamping = r.nonNegative(c, "couplingAngularDamping", p.coupling.angularDamping);
    p.coupling.maxDisplacement = r.positive(c, "maxDisplacementCells", 0.5) * cell;
    p.coupling.maxRotation = r.positive(c, "maxRotation", p.coupling.maxRotation);
  }

  // Checks.
  if (root.contains("checks")) {
    const Json& c = r.object(root, "checks");
    if (c.contains("insert")) {
      const Json& i = r.object(c, "insert");
      scene.checks.hasInsert = true;
      scene.checks.insertAxis = r.vec3(i, "axis").normalized();
      scene.checks.insertDepth = r.number(i, "depth");
    }
    if (c.contains("tunnel")) {
      const Json& t = r.object(c, "tunnel");
      scene.checks.hasTunnel = true;
      scene.checks.tunnelNormal = r.vec3(t, "normal").normalized();
      scene.checks.tunnelOffset = r.number(t, "offset");
    }
  }
  if (!scene.checks.insertAxis.allFinite() || !scene.checks.tunnelNormal.allFinite())
    throw Error(path + ": check axes must be non-zero");
  return scene;
}

}  // namespace sdfccd::haptics
