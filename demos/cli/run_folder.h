/// @file
/// @brief RunFolder: reads what `sdfccd simulate --out DIR` saved (scene.json, frames.csv) for render and plot.
///
/// @details A saved run folder holds a copy of the scene (`scene.json`), the per-frame CSV (`frames.csv`) and
/// `summary.json`. The CSV is read by its header, so extra columns and any column order are fine. Two shapes are
/// understood (README, section "Run folders"):
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
#include "sdfccd/triangle_mesh.h"

namespace sdfccd::cli {

/// One body of a run's scene.
struct RunBody {
  std::string name;
  std::string meshPath;                 ///< resolved path of the mesh file (empty for a procedural shape)
  std::shared_ptr<const TriangleMesh> mesh;  ///< loaded by loadRunMeshes()
  double scale = 1.0;                   ///< uniform scale of the mesh
  bool isStatic = false;
  Rigid worldFromBody = Rigid::Identity();   ///< the scene's initial pose (m)
};

/// The camera a scene file asks for: "camera": {"eye": [x,y,z], "target": [x,y,z], "fov": degrees, "up": [...]}.
struct RunCamera {
  Vec3 eye = Vec3::Zero();
  Vec3 target = Vec3::Zero();
  Vec3 up = Vec3::UnitY();
  double fovDegrees = 40.0;  ///< vertical field of view (degrees)
};

/// What the renderer needs from a scene file.
struct RunScene {
  std::string path;                    ///< the scene file read
  std::vector<RunBody> bodies;
  std::optional<double> groundHeight;  ///< y of the ground plane (m), when the scene has a ground
  std::optional<RunCamera> camera;
};

/// Per-frame data of a run.
struct RunFrames {
  std::vector<int> frameNumbers;                     ///< the CSV's frame numbers (0, 1, ... without a column)
  std::vector<double> times;                         ///< simulated time of each frame (s)
  std::vector<std::vector<Rigid>> worldFromBody;     ///< [frame][body], bodies in scene order
  std::map<std::string, std::vector<double>> series; ///< "contacts", "penetration", "kinetic_energy",
                                                     ///< "ccd_seconds", "step_seconds": one value per frame
};

/// File names inside a run folder.
inline constexpr const char* kRunSceneFile = "scene.json";
inline constexpr const char* kRunFramesFile = "frames.csv";
inline constexpr const char* kRunSummaryFile = "summary.json";

/// Reads the bodies, ground and camera of a scene file (the keys the renderer uses; other keys are ignored,
/// the simulate command validates them). Mesh paths that are not absolute are looked up relative to each of
/// `searchFolders` in turn, then the scene file's folder and its parents, then the current folder. Throws
/// sdfccd::Error for an unreadable file, bad JSON, a body without a mesh, or (when `resolveMeshes`) a mesh
/// found nowhere; without `resolveMeshes` an unfound mesh keeps the path as written.
RunScene readRunScene(const std::string& path, const std::vector<std::string>& searchFolders = {},
                      bool resolveMeshes = true);

/// Loads every body's mesh (each file once, shared between bodies). Throws sdfccd::Error naming the body and
/// the file if a mesh cannot be loaded.
void loadRunMeshes(RunScene& ioScene);

/// Reads frames.csv (either shape above) for the bodies of `scene`. Throws sdfccd::Error for a missing or
/// empty file, a missing time or pose column, non-numeric or non-finite values, or rows of unequal length.
RunFrames readRunFrames(const std::string& csvPath, const RunScene& scene);

/// Reads RUN_DIR/scene.json and RUN_DIR/frames.csv (meshes are not loaded). Mesh paths are also looked up
/// relative to the original scene's folder when summary.json names it ("scene" key).
struct RunFolder {
  std::string folder;
  RunScene scene;
  RunFrames frames;
};
RunFolder readRunFolder(const std::string& folder, bool resolveMeshes = true);

}  // namespace sdfccd::cli
