/// @file
/// @brief The `guard` object of scene files and haptic scene files: one reader for both (scene_guard.h).
#pragma once

#include "sdfccd/model/detail/json_reader.h"
#include "sdfccd/model/scene_guard.h"

namespace sdfccd::detail {

/// Reads the object `g` found under the key "guard": `energy_factor`, `max_speed`, `extent_factor` (each >= 1:
/// smaller factors would stop sound runs) and `action` (stop, report or off). Unknown keys and bad values are
/// one-line errors naming the key.
SceneGuard readGuard(const JsonReader& r, const Json& g);

}  // namespace sdfccd::detail
