/// @file
/// @brief Stability searches of paper Fig. 10 on a Bullet scene: one trial (is this timestep and stiffness
/// stable?), the largest stable timestep, the largest stable stiffness, and softening a model until it is stable.
///
/// @details Shared by `sdfccd bench bullet` (Fig. 10a) and the report's `stability` section. Every trial
/// simulates the scene from its start with the given penalty model, timestep and stiffness, without
/// time-of-impact clamping (so only the penalty models differ). The criterion is kStabilityCriterion. The runaway
/// guard (sdfccd/model/runaway_guard.h) watches every trial in report mode (a search must not stop at a runaway,
/// it counts it as unstable): a scene's "guard": {"action": "stop"} becomes "report", "off" stays off.
/// Searches walk a list of increasing values and stop at the first unstable one: "largest stable" is the
/// last value before it (0 when even the first is unstable).
#pragma once

#if __has_include("sdfccd/bullet/scene_world.h")  // built only with the Bullet plugin
#include <string>
#include <vector>

#include "sdfccd/bullet/contact_system.h"
#include "sdfccd/model/scene.h"

namespace sdfccd::cli {

/// What "stable" means, in one sentence (printed by the benchmark and the report).
inline constexpr const char* kStabilityCriterion =
    "stable = over the whole run no body state becomes NaN or infinite, the total energy (kinetic + "
    "gravitational potential of the dynamic bodies) never rises more than 5% + 0.5 J above its start, no "
    "body tunnels (falls through the ground), and the runaway guard (the scene's \"guard\" bounds on energy, "
    "speed and distance, in report mode) never fires";

/// One simulation run of a stability search.
struct StabilityTrialSettings {
  PenaltyModel model = PenaltyModel::Continuous;
  double timestep = 0.001;     ///< s
  double stiffness = 10000.0;  ///< N/m per point
  double duration = 1.0;       ///< simulated time (s)
  std::string cacheDir;        ///< body model cache ("" = none)
  ForceTiming forceTiming = ForceTiming::SameStep;
};

/// The outcome of one trial.
struct StabilityTrial {
  double timestep = 0.0;   ///< s
  double stiffness = 0.0;  ///< N/m per point
  bool stable = false;
  double maxPenetrationCells = 0.0;  ///< deepest point over the run (field cells)
  /// Largest rise of the total energy above its start (J); an unstable run stops at the first breach, so there it
  /// is a lower bound.
  double maxEnergyGain = 0.0;
  std::string why;      ///< "NaN", "runaway", "energy gain", "tunnelled" or "" when stable
  std::string runaway;  ///< the runaway guard's line when why == "runaway"
};

/// Runs one trial of `scene` (see the file comment). Throws sdfccd::Error on bad settings.
StabilityTrial runStabilityTrial(const Scene& scene, const StabilityTrialSettings& settings);

/// A walk over increasing timesteps or stiffnesses.
struct StabilitySearch {
  std::vector<StabilityTrial> trials;  ///< in the order run, the last one unstable unless all were stable
  double largest = 0.0;                ///< the largest stable value (0: none)
  double penetrationAtLargest = 0.0;   ///< max penetration of that trial (cells)
};

/// The largest stable timestep among `timesteps` (increasing) at `base.stiffness`; base.timestep is ignored.
StabilitySearch largestStableTimestep(const Scene& scene, const StabilityTrialSettings& base,
                                      const std::vector<double>& timesteps);
/// The largest stable stiffness among `stiffnesses` (increasing) at `base.timestep`; base.stiffness is ignored.
StabilitySearch largestStableStiffness(const Scene& scene, const StabilityTrialSettings& base,
                                       const std::vector<double>& stiffnesses);
/// Multiplies base.stiffness by `factor` (< 1) up to `attempts` times until a trial is stable; `largest` is
/// the stable stiffness found (0: none).
StabilitySearch softenUntilStable(const Scene& scene, const StabilityTrialSettings& base, double factor, int attempts);

}  // namespace sdfccd::cli

#endif
