/// @file
/// @brief The stability searches of paper Fig. 10 (see bullet_stability_search.h).
#include "bench/bullet_stability_search.h"

#if __has_include("sdfccd/bullet/scene_world.h")  // built only with the Bullet plugin
#include <algorithm>
#include <cmath>
#include <functional>

#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/model/runaway_guard.h"

namespace sdfccd::cli {

StabilityTrial runStabilityTrial(const Scene& scene, const StabilityTrialSettings& s) {
  bullet::SceneWorldSettings settings;
  settings.cacheDir = s.cacheDir;
  settings.model = s.model;
  settings.timestep = s.timestep;
  settings.stiffness = s.stiffness;
  settings.timeOfImpactClamp = false;
  settings.forceTiming = s.forceTiming;
  bullet::SceneWorld world(scene, settings);
  const double g = -scene.gravity.y();
  auto energy = [&]() {
    double e = world.kineticEnergy();
    for (int i = 0; i < world.bodyCount(); ++i) {
      if (!world.isStatic(i)) e += scene.bodies[std::size_t(i)].mass * g * world.bodyState(i).position.y();
    }
    return e;
  };
  const double start = energy();
  // The runaway guard in report mode: a violation ends the trial as unstable instead of ending the program.
  Scene guarded = scene;
  if (guarded.guard.action == GuardAction::Stop) guarded.guard.action = GuardAction::Report;
  const RunawayGuard guard(guarded, world.kineticEnergy());
  std::vector<GuardBodyState> states(static_cast<std::size_t>(world.bodyCount()));
  const int frames = static_cast<int>(std::lround(s.duration / s.timestep));
  StabilityTrial trial;
  trial.timestep = s.timestep;
  trial.stiffness = s.stiffness;
  for (int f = 0; f < frames && trial.why.empty(); ++f) {
    world.step();
    if (world.hasNonFinite()) {
      trial.why = "NaN";
      break;
    }
    for (int i = 0; i < world.bodyCount(); ++i) {
      const bullet::SceneBodyState b = world.bodyState(i);
      states[std::size_t(i)] = {b.position, b.linearVelocity};
    }
    if (const std::optional<std::string> runaway = guard.check((f + 1) * s.timestep, states, world.kineticEnergy())) {
      trial.why = "runaway";
      trial.runaway = *runaway;
      break;
    }
    const double gain = energy() - start;
    trial.maxEnergyGain = std::max(trial.maxEnergyGain, gain);
    if (gain > 0.05 * std::abs(start) + 0.5) trial.why = "energy gain";
  }
  trial.maxPenetrationCells = world.maxPenetrationCells();
  if (trial.why.empty() && !world.tunneledBodies().empty()) trial.why = "tunnelled";
  trial.stable = trial.why.empty();
  return trial;
}

namespace {

// Runs trials for increasing values until the first unstable one.
StabilitySearch walk(const std::vector<double>& values, const std::function<StabilityTrial(double)>& trialAt) {
  StabilitySearch search;
  for (const double v : values) {
    search.trials.push_back(trialAt(v));
    if (!search.trials.back().stable) break;
    search.largest = v;
    search.penetrationAtLargest = search.trials.back().maxPenetrationCells;
  }
  return search;
}

// walk() over the trials of `base` with one setting (timestep or stiffness) set to each of `values`.
StabilitySearch walkSetting(const Scene& scene, const StabilityTrialSettings& base, const std::vector<double>& values,
                            double StabilityTrialSettings::*setting) {
  return walk(values, [&](double v) {
    StabilityTrialSettings s = base;
    s.*setting = v;
    return runStabilityTrial(scene, s);
  });
}

}  // namespace

StabilitySearch largestStableTimestep(const Scene& scene, const StabilityTrialSettings& base,
                                      const std::vector<double>& timesteps) {
  return walkSetting(scene, base, timesteps, &StabilityTrialSettings::timestep);
}

StabilitySearch largestStableStiffness(const Scene& scene, const StabilityTrialSettings& base,
                                       const std::vector<double>& stiffnesses) {
  return walkSetting(scene, base, stiffnesses, &StabilityTrialSettings::stiffness);
}

StabilitySearch softenUntilStable(const Scene& scene, const StabilityTrialSettings& base, double factor, int attempts) {
  StabilitySearch search;
  StabilityTrialSettings s = base;
  for (int attempt = 0; attempt < attempts; ++attempt) {
    s.stiffness *= factor;
    search.trials.push_back(runStabilityTrial(scene, s));
    if (search.trials.back().stable) {
      search.largest = s.stiffness;
      search.penetrationAtLargest = search.trials.back().maxPenetrationCells;
      break;
    }
  }
  return search;
}

}  // namespace sdfccd::cli

#endif
