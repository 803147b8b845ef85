/// @file
/// @brief The pieces of the haptic scene reader shared by haptic_scene.cpp (the scene) and
/// haptic_scene_obstacles.cpp (the "obstacles" list and the tool's field). Internal to the haptics library.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sdfccd/haptics/haptic_scene.h"
#include "sdfccd/mesh/sdf_builder.h"
#include "sdfccd/model/detail/json_reader.h"

namespace sdfccd::haptics {

using detail::Json;
using Reader = detail::JsonReader;

/// A static field as the scene writes it (a plane, a mesh, or CSG solids and holes).
struct SceneField {
  std::shared_ptr<const GridField> grid;
  std::optional<PlaneField> plane;
  double cellSize = 0.0;  ///< model units
};

/// Reads a field object at key path `at` (the keys of "obstacle", plus `extraKeys` the caller reads itself).
SceneField readSceneField(const Reader& r, const Json& j, const std::string& at, const std::string& cacheDir,
                          const std::vector<std::string>& extraKeys);
/// A shell's mesh by its "shape" (box, cylinder, sphere, mesh, alpha-puzzle-piece, block-with-hole), in its own frame.
TriangleMesh readShellMesh(const Reader& r, const Json& j, const std::string& where);
/// The block-with-hole shape's keys ("halfExtents", "holeRadius", "segments"): blockWithHole (procedural_shapes.h).
TriangleMesh blockWithHoleMesh(const Reader& r, const Json& j, const std::string& where);
/// {"position" (required), "rotationVector"}.
Rigid readPose(const Reader& r, const Json& j, const std::string& where);
/// A mesh's exact field through the model cache (sdfccd/model/model_cache.h).
std::shared_ptr<const SdfGrid> meshObstacleGrid(const TriangleMesh& mesh, const SdfBuildSettings& build,
                                                const std::string& cacheDir, const std::string& name);
/// The "obstacles" list (haptic_scene_obstacles.cpp): fills scene.obstacles and scene.cellSize.
void readObstacles(const Reader& r, const Json& root, const std::string& cacheDir, HapticScene& scene);
/// "shell.field": the tool's field built from its (centred) mesh.
std::shared_ptr<const GridField> readToolField(const Reader& r, const Json& shellJson, const std::string& where,
                                               const TriangleMesh& centredMesh, const std::string& cacheDir);

}  // namespace sdfccd::haptics
