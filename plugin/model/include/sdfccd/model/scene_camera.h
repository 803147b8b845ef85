/// @file
/// @brief SceneCamera: the camera a scene file asks for (key "camera"), read by the renderer.
#pragma once

#include "sdfccd/math_types.h"

namespace sdfccd {

struct SceneCamera {
  Vec3 eye = Vec3::Zero();     ///< world (m)
  Vec3 target = Vec3::Zero();  ///< world (m), differs from eye
  Vec3 up = Vec3::UnitY();     ///< world
  double fovDegrees = 40.0;    ///< vertical field of view (degrees, in (0, 180))
};

}  // namespace sdfccd
