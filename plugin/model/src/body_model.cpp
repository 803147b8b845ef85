/// @file
/// @brief BodyModel: build, cache and load (see body_model.h).
#include "sdfccd/model/body_model.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sdfccd/error.h"
#include "sdfccd/field/sdf_file.h"
#include "sdfccd/mesh/sdf_builder.h"
#include "sdfccd/model/mesh_file.h"
#include "sdfccd/model/model_cache.h"
#include "sdfccd/shell/analytic_shells.h"

namespace sdfccd {
namespace {

constexpr int kCacheVersion =
    2;  // bump when the cached content changes meaning (2: self-intersecting meshes signed by winding number)

std::string readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read '" + path + "'");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

void checkSettings(const BodyModelSettings& settings) {
  if (!(settings.scale > 0.0) || !std::isfinite(settings.scale)) {
    throw Error("body model: scale must be positive and finite (got " + std::to_string(settings.scale) + ")");
  }
  if (settings.points < 0) throw Error("body model: points must be >= 0 (0: mesh vertices)");
}

PointShell makeShell(const TriangleMesh& meshInBody, const BodyModelSettings& settings) {
  if (settings.points == 0) return shellFromVertices(meshInBody);
  ShellSamplingSettings sampling;
  sampling.points = settings.points;
  sampling.threads = settings.threads;
  return sampleShell(meshInBody, sampling);
}

/// Gives a shell that has no areas (files and the cache store none) its areas (see body_model.h).
void ensureAreas(PointShell& shell, const TriangleMesh& meshInBody, int points) {
  if (shell.hasAreas() || shell.empty()) return;
  if (points == 0) {
    const PointShell vertices = shellFromVertices(meshInBody);
    if (vertices.size() == shell.size()) {
      shell.areas = vertices.areas;
      return;
    }
  }
  assignUniformAreas(shell, meshInBody.area());
}

/// The sampled surface of a box primitive (docs/design/contact-response.md, default shells), in the body frame.
PointShell boxPrimitiveShell(const Vec3& halfExtentsInModel, const BodyModelSettings& settings, double cellSize,
                             const Rigid& bodyFromModel) {
  const Vec3 half = halfExtentsInModel * settings.scale;
  AnalyticShellSettings sampling;
  sampling.spacing = std::max(cellSize, 2.0 * half.minCoeff() / 16.0);  // 16 points across the thinnest side
  PointShell shell = boxShell(half, sampling);
  for (Vec3& p : shell.positions) p = bodyFromModel * p;
  for (Vec3& n : shell.normals) n = bodyFromModel.linear() * n;
  return shell;
}

std::shared_ptr<const SdfGrid> buildGrid(const TriangleMesh& meshInBody, const BodyModelSettings& settings) {
  SdfBuildSettings build;
  build.resolution = settings.resolution;
  build.padding = settings.padding;
  build.threads = settings.threads;
  build.progress = settings.progress;
  return buildSdf(meshInBody, build).grid;
}

}  // namespace

std::shared_ptr<BodyModel> BodyModel::assemble(const TriangleMesh& meshInModel, double scale) {
  std::shared_ptr<BodyModel> model(new BodyModel());
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

std::shared_ptr<const BodyModel> BodyModel::buildFromMesh(const TriangleMesh& meshInModel,
                                                          const BodyModelSettings& settings) {
  checkSettings(settings);
  std::shared_ptr<BodyModel> model = assemble(meshInModel, settings.scale);
  model->m_field = std::make_unique<GridField>(buildGrid(model->m_meshInBody, settings));
  if (settings.boxHalfExtents && settings.points == 0) {
    model->m_tree = PointTree(boxPrimitiveShell(*settings.boxHalfExtents, settings, model->m_field->spacing(),
                                                model->m_modelFromBody.inverse()));
  } else {
    model->m_tree = PointTree(makeShell(model->m_meshInBody, settings));
  }
  return model;
}

std::shared_ptr<const BodyModel> BodyModel::buildFromMeshFile(const std::string& meshPath,
                                                              const BodyModelSettings& settings) {
  checkSettings(settings);
  const std::string bytes = readFileBytes(meshPath);
  const TriangleMesh meshInModel = loadMeshFile(meshPath);
  const ModelCache cache(settings.cacheDir);
  if (!cache.enabled()) return buildFromMesh(meshInModel, settings);

  std::ostringstream parameters;
  parameters.precision(17);
  parameters << "v" << kCacheVersion << " r" << settings.resolution << " p" << settings.padding << " n"
             << settings.points << " s" << settings.scale;
  ModelCacheKey key;
  key.add(bytes).add(parameters.str());
  const std::string name = std::filesystem::path(meshPath).stem().string();

  std::shared_ptr<BodyModel> model = assemble(meshInModel, settings.scale);
  const TriangleMesh& meshInBody = model->m_meshInBody;
  model->m_field = std::make_unique<GridField>(cache.field(name, key, [&] { return buildGrid(meshInBody, settings); }));
  PointShell shell = cache.shell(name, key, [&] { return makeShell(meshInBody, settings); });
  ensureAreas(shell, meshInBody, settings.points);
  model->m_tree = PointTree(std::move(shell));
  return model;
}

std::shared_ptr<const BodyModel> BodyModel::loadFromFiles(const std::string& meshPath, const std::string& sdfPath,
                                                          const std::string& shellPath,
                                                          const BodyModelSettings& settings) {
  checkSettings(settings);
  std::shared_ptr<BodyModel> model = assemble(loadMeshFile(meshPath), settings.scale);
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
  assignUniformAreas(shell, model->m_meshInBody.area());  // a shell file stores no areas
  model->m_tree = PointTree(std::move(shell));
  return model;
}

}  // namespace sdfccd
