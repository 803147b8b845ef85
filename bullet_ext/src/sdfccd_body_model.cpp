/// @file
/// @brief SdfccdBodyModel: build, cache and load (see sdfccd_body_model.h).
#include "sdfccd/bullet/sdfccd_body_model.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sdfccd/error.h"
#include "sdfccd/io/mesh_loader.h"
#include "sdfccd/mesh/sdf_builder.h"
#include "sdfccd/field/sdf_file.h"

namespace sdfccd {
namespace {

constexpr int kCacheVersion = 1;  // bump when the cached content changes meaning

std::string readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read '" + path + "'");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

void checkSettings(const SdfccdBodyModelSettings& settings) {
  if (!(settings.scale > 0.0) || !std::isfinite(settings.scale)) {
    throw Error("body model: scale must be positive and finite (got " + std::to_string(settings.scale) + ")");
  }
  if (settings.points < 0) throw Error("body model: points must be >= 0 (0: mesh vertices)");
}

PointShell makeShell(const TriangleMesh& meshInBody, const SdfccdBodyModelSettings& settings) {
  if (settings.points == 0) return shellFromVertices(meshInBody);
  ShellSamplingSettings sampling;
  sampling.points = settings.points;
  sampling.threads = settings.threads;
  return sampleShell(meshInBody, sampling);
}

std::shared_ptr<const SdfGrid> buildGrid(const TriangleMesh& meshInBody, const SdfccdBodyModelSettings& settings) {
  SdfBuildSettings build;
  build.resolution = settings.resolution;
  build.padding = settings.padding;
  build.threads = settings.threads;
  build.progress = settings.progress;
  return buildSdf(meshInBody, build).grid;
}

}  // namespace

std::uint64_t fnv1a64(const std::string& bytes, std::uint64_t seed) {
  // Written out because std::hash is neither specified nor stable across library versions.
  std::uint64_t h = seed;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::shared_ptr<SdfccdBodyModel> SdfccdBodyModel::assemble(const TriangleMesh& meshInModel, double scale) {
  std::shared_ptr<SdfccdBodyModel> model(new SdfccdBodyModel());
  TriangleMesh scaled = meshInModel;
  for (Vec3& v : scaled.vertices) v *= scale;
  MassPropertiesSettings unitDensity;
  unitDensity.density = 1.0;
  const MassProperties inModel = computeMassProperties(scaled, unitDensity);

  const BodyFrame frame = bodyFrameOf(inModel);
  const Rigid& modelFromBody = frame.modelFromBody;
  model->m_modelFromBody = modelFromBody;

  const Rigid bodyFromModel = modelFromBody.inverse();
  model->m_meshInBody = scaled;
  for (Vec3& v : model->m_meshInBody.vertices) v = bodyFromModel * v;
  model->m_mass = inModel;
  model->m_mass.centerOfMassInMesh = Vec3::Zero();
  model->m_mass.inertiaAboutCenterOfMass = frame.inertiaInBody;
  model->m_mass.principalAxesInMesh = Mat3::Identity();
  model->m_mass.principalMoments = frame.principalMoments();
  model->m_boundsInBody = Box3();
  for (const Vec3& v : model->m_meshInBody.vertices) model->m_boundsInBody.extend(v);
  return model;
}

std::shared_ptr<const SdfccdBodyModel> SdfccdBodyModel::buildFromMesh(const TriangleMesh& meshInModel,
                                                                      const SdfccdBodyModelSettings& settings) {
  checkSettings(settings);
  std::shared_ptr<SdfccdBodyModel> model = assemble(meshInModel, settings.scale);
  model->m_field = std::make_unique<GridField>(buildGrid(model->m_meshInBody, settings));
  model->m_tree = PointTree(makeShell(model->m_meshInBody, settings));
  return model;
}

std::shared_ptr<const SdfccdBodyModel> SdfccdBodyModel::buildFromMeshFile(const std::string& meshPath,
                                                                          const SdfccdBodyModelSettings& settings) {
  checkSettings(settings);
  const std::string bytes = readFileBytes(meshPath);
  const TriangleMesh meshInModel = loadMesh(meshPath);
  if (settings.cacheDir.empty()) return buildFromMesh(meshInModel, settings);

  std::ostringstream parameters;
  parameters.precision(17);
  parameters << "v" << kCacheVersion << " r" << settings.resolution << " p" << settings.padding << " n"
             << settings.points << " s" << settings.scale;
  const std::uint64_t key = fnv1a64(parameters.str(), fnv1a64(bytes));
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(key));
  const std::string stem = std::filesystem::path(meshPath).stem().string();
  const std::filesystem::path base = std::filesystem::path(settings.cacheDir) / (stem + "-" + hex);
  const std::string sdfPath = base.string() + ".sdf";
  const std::string shellPath = base.string() + ".ply";

  std::shared_ptr<SdfccdBodyModel> model = assemble(meshInModel, settings.scale);
  if (std::filesystem::exists(sdfPath) && std::filesystem::exists(shellPath)) {
    try {
      model->m_field = std::make_unique<GridField>(std::make_shared<const SdfGrid>(loadSdf(sdfPath)));
      model->m_tree = PointTree(loadShell(shellPath));
      model->m_fromCache = true;
      return model;
    } catch (const Error&) {
      // A damaged cache entry is rebuilt below and overwritten.
    }
  }
  std::error_code ignored;
  std::filesystem::create_directories(settings.cacheDir, ignored);
  std::shared_ptr<const SdfGrid> grid = buildGrid(model->m_meshInBody, settings);
  PointShell shell = makeShell(model->m_meshInBody, settings);
  saveSdf(sdfPath, *grid, SdfFileFormat::Native);
  saveShell(shell, shellPath);
  model->m_field = std::make_unique<GridField>(std::move(grid));
  model->m_tree = PointTree(std::move(shell));
  return model;
}

std::shared_ptr<const SdfccdBodyModel> SdfccdBodyModel::loadFromFiles(const std::string& meshPath,
                                                                      const std::string& sdfPath,
                                                                      const std::string& shellPath,
                                                                      const SdfccdBodyModelSettings& settings) {
  checkSettings(settings);
  std::shared_ptr<SdfccdBodyModel> model = assemble(loadMesh(meshPath), settings.scale);
  const double s = settings.scale;
  SdfGrid loaded = loadSdf(sdfPath);
  std::vector<float> values = loaded.values();
  if (s != 1.0) {
    for (float& v : values) v = static_cast<float>(v * s);
  }
  model->m_field = std::make_unique<GridField>(std::make_shared<const SdfGrid>(
      loaded.nodeCounts(), loaded.origin() * s, loaded.spacing() * s, std::move(values)));
  model->m_bodyFromField = model->m_modelFromBody.inverse();
  PointShell shell = loadShell(shellPath);
  const Rigid bodyFromModel = model->m_modelFromBody.inverse();
  for (Vec3& p : shell.positions) p = bodyFromModel * Vec3(p * s);
  for (Vec3& n : shell.normals) n = bodyFromModel.linear() * n;
  model->m_tree = PointTree(std::move(shell));
  return model;
}

}  // namespace sdfccd
