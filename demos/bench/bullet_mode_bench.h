/// @file
/// @brief `sdfccd bench bullet --part modes` and `--part stable`: the two contact modes (docs/bullet.md) beside
/// Bullet's own shapes on the 20-bunny drop and on a box stack, and the largest stable step of each.
///
/// @details Contenders, each in its own world, the same scene (bodies, masses, inertia, poses, ground, sleeping):
/// - penalty: SdfccdShape, `contact.mode: penalty` with the project's contact defaults (what a new world gets), at
///   1 ms; on the bunnies also drop-bunnies as shipped (the paper's per-point stiffness and shell normal);
/// - solver: SdfccdShape, `contact.mode: solver` with the defaults, at 1/240 s (Bullet's usual fixed step), and the
///   same with `contact.solver: sequential_impulse` (Bullet's default solver instead of the default MLCP solver: what
///   the exact solver costs);
/// - GImpact: btGImpactMeshShape of the same meshes, at 1/240 s (gimpact_peer.h);
/// - convex: btConvexHullShape of the mesh's hull vertices, btBoxShape for boxes (Bullet's fast path) at 1/240 s.
/// Step time is thread CPU time of the steps alone (one thread); it is also given per simulated second, so that
/// steps of different length compare. Penetration and tunnelling come from the poses alone, the same way for
/// every contender (penetration_probe.h: mesh vertices below the ground and in the other body's field).
///
/// The stability search walks each mode's list of steps upwards and stops at the first unstable one; the
/// criterion is kModeStabilityCriterion.
#pragma once

#if __has_include("sdfccd/bullet/scene_world.h")  // built only with the Bullet plugin
#include <functional>
#include <string>

namespace sdfccd::cli {

/// What "stable" means for a contact mode, in one sentence (%g: the penetration bound in cells, then the
/// probe's interval in ms).
inline constexpr const char* kModeStabilityCriterion =
    "stable = over the whole run no body state becomes NaN or infinite, the total energy (kinetic + "
    "gravitational potential of the dynamic bodies) never rises more than 5%% + 0.5 J above its start, the runaway "
    "guard (the scene's \"guard\" bounds, in report mode) never fires, no body "
    "tunnels (centre of mass below the ground or inside another body), and no mesh vertex is ever deeper than "
    "%g field cells in the ground or in another body (sampled every %g ms of simulated time)";

struct ModeBenchOptions {
  bool quick = false;
  std::string scenes = "assets/scenes";
  std::string cache;                 ///< the model cache folder (bench bullet's --cache); "": none
  double gimpactSeconds = 0.4;       ///< simulated time of the GImpact world (its steps cost seconds)
  double maxPenetrationCells = 8.0;  ///< the criterion's penetration bound: half a bunny's thickness at 128^3
  double timingSeconds = 1.0;        ///< simulated time of the timing runs (--quick: less)
};

/// Receives one CSV row (part, item, key, value).
using CsvSink = std::function<void(const std::string&, const std::string&, const std::string&, double)>;

/// Step time, penetration and tunnelling of every contender on the 20-bunny drop and the box stack.
void runModeTiming(const ModeBenchOptions& options, const CsvSink& csv);
/// The largest stable step of each mode on the 20-bunny drop and the box stack.
void runModeStability(const ModeBenchOptions& options, const CsvSink& csv);

}  // namespace sdfccd::cli

#endif
