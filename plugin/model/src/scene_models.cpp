/// @file
/// @brief buildSceneModels (scene_models.h).
#include "sdfccd/model/scene_models.h"

#include <map>
#include <sstream>

namespace sdfccd {
namespace {

/// Bodies with equal keys share a model.
std::string modelKey(const SceneBody& b) {
  std::ostringstream key;
  key.precision(17);
  key << b.mesh << "|" << b.sdf << "|" << b.shell << "|" << b.scale << "|" << b.points << "|" << b.resolution << "|"
      << b.padding << "|" << b.pointsGiven;
  if (b.primitive) {
    const ScenePrimitive& p = *b.primitive;
    key << "|" << p.type << " " << p.halfExtents.transpose() << " " << p.radius << " " << p.height << " "
        << p.subdivisions;
  }
  return key.str();
}

}  // namespace

std::vector<std::shared_ptr<const BodyModel>> buildSceneModels(const Scene& scene, const SceneModelSettings& settings) {
  std::vector<std::shared_ptr<const BodyModel>> models;
  std::map<std::string, std::shared_ptr<const BodyModel>> shared;
  for (const SceneBody& b : scene.bodies) {
    const std::string key = modelKey(b);
    auto found = shared.find(key);
    if (found == shared.end()) {
      BodyModelSettings ms;
      ms.resolution = b.resolution;
      ms.padding = b.padding;
      ms.points = b.points;
      ms.scale = b.scale;
      ms.threads = settings.threads;
      ms.cacheDir = settings.cacheDir;
      if (b.primitive && b.primitive->type == "box" && !b.pointsGiven) ms.boxHalfExtents = b.primitive->halfExtents;
      std::shared_ptr<const BodyModel> model;
      if (b.primitive) {
        model = BodyModel::buildFromMesh(makePrimitiveMesh(*b.primitive), ms);
      } else if (!b.sdf.empty()) {
        model = BodyModel::loadFromFiles(b.mesh, b.sdf, b.shell, ms);
      } else {
        model = BodyModel::buildFromMeshFile(b.mesh, ms);
      }
      found = shared.emplace(key, model).first;
    }
    models.push_back(found->second);
    if (settings.progress) settings.progress(double(models.size()) / double(scene.bodies.size()));
  }
  return models;
}

}  // namespace sdfccd
