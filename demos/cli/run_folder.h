/// @file
/// @brief RunFolder: reads what `sdfccd simulate --out DIR` saved (scene.json, frames.csv) for render and plot.
///
/// @details A saved run folder holds a copy of the scene (`scene.json`), the per-frame CSV (`frames.csv`) and
/// `summary.json`. The CSV is read by its header, so extra columns and any column order are fine. Two shapes are
/// understood (docs/cli.md, run folders):
/// - long: one row per frame and body, with a `body` (or `name`) column and `px,py,pz,qw,qx,qy,qz`; rows of one
///   frame share the `frame` column (or, without it, the `time`);
/// - wide: one row per frame, with `<body>.px` ... `<body>.qz` (or `<body>_px`) columns for every scene body.
/// Per-frame series for plots are gathered from columns named (any of) `contacts`/`contact_count`,
/// `penetration`/`max_penetration`, `kinetic_energy`, `ccd_seconds`/`ccd_time`, `step_seconds`/`step_time`:
/// per-body values are summed (contacts, energy, times) or maxed (penetration) over the bodies of a frame.
/// Bodies missing from the CSV (e.g. static ones) keep the pose the scene gives them.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"
#include "sdfccd/model/scene_camera.h"
#include "sdfccd/model/scene_primitive.h"

namespace sdfccd::cli {

/// One body of a run's scene.
///
/// Poses are of the *body frame* the simulation integrates (BodyModel, sdfccd/model/body_model.h): origin at
/// the centre of mass, axes along the principal axes of inertia unless the mesh's own axes already are
/// principal. loadRunMeshes() puts the scaled mesh into that frame the same way, so `worldFromBody * vertex`
/// places it.
struct RunBody {
  std::string name;
  std::string meshPath;  ///< resolved path of the mesh file (empty for a primitive)
  std::optional<ScenePrimitive> primitive;
  double scale = 1.0;  ///< uniform scale of the mesh (baked into `mesh`)
  double mass = 1.0;   ///< kg (0 for static bodies)
  bool isStatic = false;
  Quat orientationAtStart = Quat::Identity();  ///< the scene's "orientation" (of the mesh's own axes)
  Vec3 positionAtStart = Vec3::Zero();         ///< the scene's "position" (of the centre of mass, m)
  // Filled by loadRunMeshes():
  std::shared_ptr<const TriangleMesh> mesh;  ///< scaled, in the body frame (m)
  Vec3 principalInertia = Vec3::Zero();      ///< body-frame diagonal inertia for `mass` (kg m^2)
  Rigid worldFromBody = Rigid::Identity();   ///< the pose at the start (m)
};

/// What the renderer needs from a scene file.
struct RunScene {
  std::string path;  ///< the scene file read
  std::vector<RunBody> bodies;
  std::optional<double> groundHeight;  ///< y of the ground plane (m), when the scene has a ground
  std::optional<SceneCamera> camera;
};

/// Per-frame data of a run.
struct RunFrames {
  std::vector<int> frameNumbers;                      ///< the CSV's frame numbers (0, 1, ... without a column)
  std::vector<double> times;                          ///< simulated time of each frame (s)
  std::vector<std::vector<Rigid>> worldFromBody;      ///< [frame][body], bodies in scene order
  std::map<std::string, std::vector<double>> series;  ///< "contacts", "penetration", "kinetic_energy",
                                                      ///< "ccd_seconds", "step_seconds": one value per frame
  std::map<std::string, std::string> seriesSource;    ///< the CSV column (or "computed") behind each series
};

/// File names inside a run folder.
inline constexpr const char* kRunSceneFile = "scene.json";
inline constexpr const char* kRunFramesFile = "frames.csv";
inline constexpr const char* kRunSummaryFile = "summary.json";

/// Reads the bodies, ground and camera of a scene file with the model layer's scene reader (loadScene,
/// sdfccd/model/scene.h: the same strict validation as `sdfccd simulate`). File paths that are not absolute are
/// looked up relative to the current folder, then the scene file's folder and its ancestors, then each of
/// `searchFolders` in turn. Throws sdfccd::Error (one line naming the file and the key) for any defect, or (when
/// `resolveMeshes`) a file found nowhere; without `resolveMeshes` an unfound file keeps the path as written.
RunScene readRunScene(const std::string& path, const std::vector<std::string>& searchFolders = {},
                      bool resolveMeshes = true);

/// Loads every body's mesh (each file or primitive once, shared between bodies), scales it and moves it into the
/// body frame; fills mass properties and start poses. Throws sdfccd::Error naming the body and the file if a
/// mesh cannot be loaded or encloses no volume.
void loadRunMeshes(RunScene& ioScene);

/// The body frame of a scaled mesh: `modelFromBody` maps body coordinates to (scaled) mesh coordinates, by
/// bodyFrameOf (mass_properties.h), the rule BodyModel (sdfccd/model/body_model.h) uses too.
Rigid modelFromBodyOf(const TriangleMesh& scaledMeshInModel, Vec3* outUnitDensityPrincipalMoments = nullptr,
                      double* outUnitDensityMass = nullptr);

/// Reads frames.csv (either shape above) for the bodies of `scene`. Without a kinetic energy column, the
/// "kinetic_energy" series is computed from the velocity columns (vx..vz, wx..wz, world frame) when the meshes
/// are loaded (masses and inertias known). Throws sdfccd::Error for a missing or
/// empty file, a missing time or pose column, non-numeric or non-finite values, or rows of unequal length.
RunFrames readRunFrames(const std::string& csvPath, const RunScene& scene);

/// Reads a run folder: the scene (RUN_DIR/scene.json, else the file summary.json names under "scene"), then
/// frames.csv. Meshes are loaded (loadRunMeshes) when `loadMeshes`; mesh paths are also looked up relative to the
/// original scene's folder. Without `loadMeshes`, unfound meshes are no error (plots need no meshes).
struct RunFolder {
  std::string folder;
  RunScene scene;
  RunFrames frames;
};
RunFolder readRunFolder(const std::string& folder, bool loadMeshes = true);

}  // namespace sdfccd::cli
