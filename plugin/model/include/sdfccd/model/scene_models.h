/// @file
/// @brief buildSceneModels: the body models of a scene's bodies, one per distinct shape and build parameters
/// (twenty bunnies, one field), for the Bullet plugin's SceneWorld and any other world built from a scene.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sdfccd/model/body_model.h"
#include "sdfccd/model/scene.h"
#include "sdfccd/progress.h"

namespace sdfccd {

/// How a scene's models are built (what does not belong in the scene file).
struct SceneModelSettings {
  std::string cacheDir;       ///< model cache for mesh files (model_cache.h); "" = none
  int threads = 0;            ///< threads for building fields and shells (0 = all cores)
  ProgressCallback progress;  ///< fraction of the scene's bodies whose model is ready
};

/// One model per body of `scene`, in body order; bodies with the same mesh (or primitive), files and build
/// parameters share one model. A primitive is built from its mesh (scene_primitive.h), a body with "sdf" and
/// "shell" is assembled from those files (BodyModel::loadFromFiles), any other from its mesh file through the
/// model cache. Throws sdfccd::Error on bad meshes or files.
std::vector<std::shared_ptr<const BodyModel>> buildSceneModels(const Scene& scene, const SceneModelSettings& settings);

}  // namespace sdfccd
