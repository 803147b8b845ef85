/// @file
/// @brief Reading a haptic run folder (`sdfccd haptics SCENE --out DIR`) for `sdfccd render` and `sdfccd plot`.
///
/// @details A haptic run folder holds ticks.csv (one row per haptic tick: the device pose, the simulated tool's
/// pose `sim_*`, the force and torque on the device, contacts, penetration) and summary.json, whose "scene_file"
/// names the scene file (absolute path) the session ran. A folder is a haptic run when it has ticks.csv and no
/// frames.csv (the simulate runs' file). Rendering reloads the scene (loadHapticScene: the tool's mesh in its body
/// frame, the obstacle's field, from the model cache when built before) and draws the tool at its recorded poses
/// and the obstacle as the blocky surface of its field's inside nodes (a plane as a thin square slab).
#pragma once

#include <string>
#include <vector>

#include "cli/run_folder.h"

namespace sdfccd::cli {

/// The file a haptic run's ticks are in.
inline constexpr const char* kHapticTicksFile = "ticks.csv";

/// True when `folder` holds ticks.csv and no frames.csv.
bool isHapticRunFolder(const std::string& folder);

/// The ticks of a haptic run as RunFrames with one body (the simulated tool, pose columns sim_*): frame numbers
/// are the ticks, times the ticks' times (s); series "force" and "torque" (magnitudes, N and N m), "contacts" and
/// "penetration" (model units, source "penetration_m"). Throws sdfccd::Error with one line naming the file (and
/// line) for a missing file or column, a row of the wrong length (a truncated file), a value that is not a
/// finite number, or fewer or more rows than summary.json's "haptic_ticks" (when there is a summary and the
/// session ended without an error).
RunFrames readHapticTicks(const std::string& folder);

/// The scene file of a haptic run: summary.json's "scene_file". Throws sdfccd::Error naming summary.json when
/// it is missing, unreadable or has no "scene_file".
std::string hapticRunSceneFile(const std::string& folder);

/// A haptic run ready to render: bodies {tool, obstacle} with meshes, and frames whose poses are
/// {tool, obstacle} per tick. `cacheDir` is the model cache for fields built from meshes ("" = none).
/// Throws sdfccd::Error as readHapticTicks, hapticRunSceneFile and loadHapticScene do.
RunFolder readHapticRunFolder(const std::string& folder, const std::string& cacheDir);

}  // namespace sdfccd::cli
