/// @file
/// @brief Scene: a simulation scenario read from JSON (assets/scenes/*.json), strictly validated.
///
/// @details Scenes are data shared by tests, benchmarks and demos (README "Scene files" lists every key).
/// Validation is strict: unknown keys, wrong types, missing files, non-positive masses of dynamic bodies,
/// non-finite numbers, non-unit quaternions and unknown effects are each a one-line sdfccd::Error naming the
/// scene and the key (e.g. "scene 'x.json': bodies[2].mass must be > 0 (got -1)").
///
/// Effects: only what a scene lists is simulated — "gravity" (else zero gravity), "ground" (else no ground
/// plane and no ground field), "damping" (else no damping integrals), "rotation" (else no contact torques and
/// the bodies do not rotate), "friction" (regularized Coulomb friction, beyond the paper; else none).
#pragma once

#include <array>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sdfccd/bullet/sdfccd_contact_system.h"
#include "sdfccd/math_types.h"
#include "sdfccd/response/penalty_model.h"

namespace sdfccd {

/// A procedural body shape (procedural_meshes.h), instead of a mesh file.
struct ScenePrimitive {
  std::string type;                        ///< "box", "sphere", "cylinder" or "bowl"
  Vec3 halfExtents = Vec3::Constant(0.5);  ///< box (model units)
  double radius = 0.5;                     ///< sphere, cylinder; the bowl's rim radius
  double height = 1.0;                     ///< cylinder; the bowl's height
  int subdivisions = 3;                    ///< sphere
};

struct SceneBody {
  std::string name;
  std::string mesh;  ///< resolved path of the mesh file; empty for a primitive
  std::optional<ScenePrimitive> primitive;
  std::string sdf;                      ///< optional precomputed field (with "shell"), resolved path
  std::string shell;                    ///< optional precomputed shell, resolved path
  double scale = 1.0;                   ///< uniform scale of the mesh
  double mass = 1.0;                    ///< kg (ignored for static bodies)
  Vec3 position = Vec3::Zero();         ///< of the centre of mass, world (m)
  Quat orientation = Quat::Identity();  ///< of the mesh's own axes, world
  Vec3 velocity = Vec3::Zero();         ///< m/s, of the centre of mass
  Vec3 angularVelocity = Vec3::Zero();  ///< rad/s, world
  bool isStatic = false;
  int points = 0;       ///< shell points (0: mesh vertices)
  int resolution = 64;  ///< SDF cells along the longest side
  int padding = 4;      ///< SDF padding cells
};

struct SceneContact {
  PenaltyModel model = PenaltyModel::Continuous;
  double stiffness = 2000.0;  ///< N/m per point
  double damping = 5.0;       ///< N s/m per point (used only with the "damping" effect)
  double friction = 0.5;      ///< Coulomb coefficient (used only with the "friction" effect; beyond the paper)
  int subintervals = 5;
  bool timeOfImpactClamp = true;  ///< continuous model only
  double toiDepthCells = 0.5;
  bool useTree = true;
  SdfccdForceTiming forceTiming = SdfccdForceTiming::SameStep;  ///< when the penalty impulses act
  /// The paper's shell normal by default: robust where points sink deep (the field's gradient turns at thin
  /// parts: the 20-bunny drop's largest stable timestep is 2.5 ms with it, 1 ms with the gradient), but not
  /// conservative (a box resting on its 8 corner points drifts; tests/bullet/stability_test.cpp), where
  /// "field_gradient" is the choice.
  PenaltyDirection direction = PenaltyDirection::ShellNormal;   ///< "direction": shell_normal or field_gradient
};

struct Scene {
  std::string path;  ///< the file it came from ("" when parsed from text)
  std::string name;
  double timestep = 0.001;           ///< s
  int frames = 1000;                 ///< steps of `timestep`
  Vec3 gravity = Vec3(0, -9.81, 0);  ///< m/s^2, used only with the "gravity" effect
  std::set<std::string> effects;
  double groundHeight = 0.0;  ///< m, used only with the "ground" effect
  bool sleeping = true;       ///< bodies at rest may sleep (Bullet's thresholds); false: always simulated
  SceneContact contact;
  std::vector<SceneBody> bodies;

  bool has(const std::string& effect) const { return effects.count(effect) != 0; }
  /// The active effects, sorted, comma-separated.
  std::string effectList() const;
};

/// Reads and validates a scene file; relative mesh paths are tried against the current folder, then the
/// scene's folder and its ancestors (so "assets/meshes/bunny.off" works for scenes in assets/scenes/).
/// Throws sdfccd::Error (one line) on any defect.
Scene loadScene(const std::string& path);
/// Parses scene JSON text; `name` appears in errors; relative paths resolve against `baseDir` and its
/// ancestors.
Scene parseScene(const std::string& text, const std::string& name, const std::string& baseDir);

}  // namespace sdfccd
