/// @file
/// @brief HapticScene: one haptics experiment as data (assets/scenes/haptics/*.json), shared by the CLI,
/// the tests and the benchmarks (paper Section 5, "Haptic Rendering").
///
/// @details A scene holds the static object (a grid field, or an analytic plane), the manipulated point
/// shell with its mass properties, the scripted user, and the settings of the device and of both
/// renderers, in the scene's own units (metres in the shipped scenes). Contact tolerances are written in
/// voxels ("cells") in the file and converted with the field's spacing.
///
/// Reading goes through the model layer's strict reader (sdfccd/model/detail/json_reader.h): unknown keys, wrong
/// types and absurd values are one-line sdfccd::Error naming the file and the key path; mesh files are read by
/// loadMeshFile (sdfccd/model/mesh_file.h) and looked up like the files of simulation scenes (the current
/// folder, then the scene's folder and its ancestors); fields built from meshes are kept in the model cache
/// (sdfccd/model/model_cache.h).
///
/// Static objects come from a mesh file (buildSdf, exact distances) or are built on the grid from exact box,
/// cylinder and capsule signed distances combined by CSG: phi = max(min_i solid_i, -min_j hole_j). Its zero level set
/// is the exact boundary, and near flat walls the values are the exact distances, so a field offset of 0.1 voxel
/// ("fieldOffsetCells", field values minus 0.1 * spacing: the paper's shrunk hole) is exactly 0.1 voxel; a closed
/// cavity (the stuck case of Fig. 13) is one hole. Shells come from the procedural meshes (box, cylinder, icosphere),
/// sampled by particle repulsion (point_shell.h).
///
/// File format: see docs/scene-format.md.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/haptics/device_emulator.h"
#include "sdfccd/haptics/god_object.h"
#include "sdfccd/haptics/haptic_obstacles.h"
#include "sdfccd/haptics/penalty_renderer.h"
#include "sdfccd/haptics/user_script.h"
#include "sdfccd/mesh/triangle_mesh.h"
#include "sdfccd/model/scene_guard.h"
#include "sdfccd/shell/point_tree.h"

namespace sdfccd::haptics {

/// A CSG primitive of the static object, in the field's frame: a box (axis-aligned), a finite cylinder along any
/// axis, or a capsule (the points within `radius` of a segment: struts and wires at any angle, Figs. 8 and 12).
struct CsgPrimitive {
  enum class Kind { Box, Cylinder, Capsule } kind = Kind::Box;
  Vec3 center = Vec3::Zero();                  ///< box and cylinder: centre; capsule: one end of its segment
  Vec3 halfExtents = Vec3::Zero();             ///< box: half sizes
  Vec3 axis = Vec3::UnitY();                   ///< cylinder: unit axis
  Vec3 end = Vec3::Zero();                     ///< capsule: the segment's other end
  double radius = 0.0;                         ///< cylinder, capsule (model units)
  double halfHeight = 0.0;                     ///< cylinder: half its length along `axis` (model units)
  double signedDistance(const Vec3& p) const;  ///< exact signed distance (model units)
  /// A box holding the primitive. Throws sdfccd::Error on a non-positive or non-finite size or a non-unit axis.
  Box3 bounds() const;
};

/// The static object of a scene as CSG (before sampling).
struct CsgObstacle {
  std::vector<CsgPrimitive> solids;
  std::vector<CsgPrimitive> holes;
  double spacing = 0.0;                        ///< cell edge (model units)
  int paddingCells = 3;                        ///< cells around the solids' box
  double offsetCells = 0.0;                    ///< subtract offsetCells * spacing from every value (grows the object)
  double signedDistance(const Vec3& p) const;  ///< CSG value before the offset
};

/// Samples the CSG obstacle on a grid. Throws sdfccd::Error on no solids, bad spacing, or more than
/// 64 M nodes.
std::shared_ptr<const SdfGrid> sampleCsgObstacle(const CsgObstacle& obstacle);

/// What a session checks.
struct HapticSceneChecks {
  bool hasInsert = false;
  Vec3 insertAxis = -Vec3::UnitY();  ///< unit: "inserted" when the body's centre reaches insertDepth along it
  double insertDepth = 0.0;          ///< model units
  bool hasTunnel = false;
  Vec3 tunnelNormal = -Vec3::UnitY();  ///< unit: "tunneled" when normal . centre > tunnelOffset
  double tunnelOffset = 0.0;           ///< model units
};

struct HapticScene {
  std::string name;
  std::string description;
  // The static object: a grid field, or an analytic plane when `plane` is set.
  std::shared_ptr<const GridField> grid;
  std::optional<PlaneField> plane;
  Rigid worldFromSdf = Rigid::Identity();
  double cellSize = 0.0;  ///< the field's spacing (plane: a nominal cell used for tolerances), model units;
                          ///< with "obstacles": the finest cell of their fields and the tool's field
  /// Several obstacles (scene key "obstacles", haptic_obstacles.h), each a field or a point shell, static or
  /// moving. Empty: the one static object above (key "obstacle"); when set, grid and plane are empty.
  std::vector<HapticObstacle> obstacles;
  /// The tool's own field (scene key "shell.field"), in its body frame (origin at the centre of mass): what shell
  /// obstacles collide with. Null: none.
  std::shared_ptr<const GridField> toolField;
  // The manipulated object.
  std::shared_ptr<const PointTree> tree;
  std::shared_ptr<const TriangleMesh> shellMesh;  ///< the procedural mesh the shell was sampled from
  int shellIterations = 10;                       ///< repulsion iterations used for the shell
  double mass = 0.0;                              ///< kg
  Vec3 inertiaDiagonal = Vec3::Zero();            ///< kg m^2, body axes
  Rigid worldFromBodyStart = Rigid::Identity();
  // The user and the loops.
  UserScript script;
  double seconds = 0.0;  ///< default session length (s)
  DeviceSettings device;
  GodObjectSettings god;
  PenaltyRendererSettings penalty;
  HapticSceneChecks checks;
  /// "guard": the runaway watchdog of the simulated object (same keys and defaults as a simulation scene's
  /// guard, sdfccd/model/scene_guard.h): on a runaway the device force goes to zero and the loop stops.
  SceneGuard guard;
};

/// Replaces the scene's shell by `points` points sampled from its mesh (for point-count sweeps). Throws
/// sdfccd::Error on points < 1.
void resampleSceneShell(HapticScene& scene, int points);

/// How a scene file is loaded.
struct HapticSceneLoadSettings {
  /// Folder of the model cache (sdfccd/model/model_cache.h) where the fields built from meshes (buildSdf: seconds
  /// to minutes at 512^3) are kept, keyed by the mesh's content and the build parameters ("<name>-<key>.sdf",
  /// native format); "": no cache.
  std::string cacheDir;
};

/// Loads a scene file. Throws sdfccd::Error (one line naming the file and the key) on a missing file, bad JSON,
/// unknown keys, missing or absurd values, or a mesh file this build cannot read. A damaged cache entry is rebuilt
/// and overwritten.
HapticScene loadHapticScene(const std::string& path, const HapticSceneLoadSettings& settings = {});

}  // namespace sdfccd::haptics
