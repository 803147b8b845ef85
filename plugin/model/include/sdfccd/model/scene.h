/// @file
/// @brief Scene: a simulation scenario read from JSON (assets/scenes/*.json), strictly validated; the one reader
/// of scene files, used by the Bullet plugin, the tool (simulate, render, plot) and the fuzzer alike.
///
/// @details Scenes are data shared by tests, benchmarks and demos (docs/scene-format.md lists every key).
/// Validation is strict: unknown keys, wrong types, missing files, non-positive masses of dynamic bodies,
/// non-finite numbers, non-unit quaternions and unknown effects are each a one-line sdfccd::Error naming the
/// scene and the key (e.g. "scene 'x.json': bodies[2].mass must be > 0 (got -1)").
///
/// Effects: only what a scene lists is simulated — "gravity" (else zero gravity), "ground" (else no ground
/// plane and no ground field), "damping" (else no damping integrals), "rotation" (else no contact torques and
/// the bodies do not rotate), "friction" (regularized Coulomb friction, beyond the paper; else none).
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/model/scene_body.h"
#include "sdfccd/model/scene_camera.h"
#include "sdfccd/model/scene_contact.h"
#include "sdfccd/model/scene_guard.h"

namespace sdfccd {

struct Scene {
  std::string path;  ///< the file it came from ("" when parsed from text)
  std::string name;
  double timestep = 0.001;           ///< s
  int frames = 1000;                 ///< steps of `timestep`
  Vec3 gravity = Vec3(0, -9.81, 0);  ///< m/s^2, used only with the "gravity" effect
  std::set<std::string> effects;
  double groundHeight = 0.0;          ///< m, used only with the "ground" effect
  /// The ground's material, combined with each body's the Bullet way (products): 1 and 1 give a body on the
  /// ground its own friction and restitution.
  double groundFriction = 1.0;
  double groundRestitution = 1.0;
  bool sleeping = true;               ///< bodies at rest may sleep (Bullet's thresholds); false: always simulated
  std::optional<SceneCamera> camera;  ///< for the renderer; empty: automatic framing
  SceneContact contact;
  SceneGuard guard;  ///< "guard": the runaway watchdog's limits (sdfccd/model/runaway_guard.h)
  std::vector<SceneBody> bodies;

  bool has(const std::string& effect) const { return effects.count(effect) != 0; }
  /// The active effects, sorted, comma-separated.
  std::string effectList() const;
};

/// The folder name a scene's default run folder gets (`sdfccd simulate` without --out: out/simulate/<this>).
/// A scene's "name" is data, never a path: every byte outside [A-Za-z0-9._-] (slashes, newlines, control
/// characters, spaces, non-ASCII) becomes '_', a leading '.' becomes '_' (so no "." or ".." and no hidden
/// folder), the result is cut to 64 bytes, and an empty name gives "scene". Names that are already safe are
/// returned unchanged.
std::string sceneFolderName(const std::string& name);

/// Where the files a scene names (mesh, sdf, shell) are looked for.
struct SceneLoadSettings {
  /// Folders tried after the usual ones (see loadScene), in order: e.g. a run folder and the folder of the scene
  /// it was copied from.
  std::vector<std::string> searchFolders;
  /// true: a file found nowhere is an error; false: it keeps the path as written (readers that need no files).
  bool requireFiles = true;
};

/// Reads and validates a scene file; relative file paths are tried against the current folder, then the scene's
/// folder and its ancestors (so "assets/meshes/bunny.off" works for scenes in assets/scenes/), then
/// settings.searchFolders. Throws sdfccd::Error (one line) on any defect.
Scene loadScene(const std::string& path, const SceneLoadSettings& settings = {});
/// Parses scene JSON text; `name` appears in errors; relative paths resolve against the current folder, then
/// `baseDir` and its ancestors, then settings.searchFolders.
Scene parseScene(const std::string& text, const std::string& name, const std::string& baseDir,
                 const SceneLoadSettings& settings = {});

}  // namespace sdfccd
