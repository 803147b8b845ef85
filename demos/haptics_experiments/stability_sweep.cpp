/// @file
/// @brief Fig. 10b: the largest stable penalty stiffness of a scene (see stability_sweep.h).
#include "haptics_experiments/stability_sweep.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "sdfccd/error.h"

namespace sdfccd::haptics {

namespace {

std::string describe(const char* what, double value, double limit) {
  char text[160];
  std::snprintf(text, sizeof text, "%s %.3g > %.3g", what, value, limit);
  return text;
}

}  // namespace

StabilityRun runAtStiffness(const HapticScene& sceneIn, HapticMethod method, double stiffness,
                            const StabilityCriteria& criteria, const HapticSessionSettings& base) {
  if (method != HapticMethod::Penalty && method != HapticMethod::DiscretePenalty)
    throw Error("stability sweep: the method must be penalty or discrete-penalty");
  HapticScene scene = sceneIn;
  scene.penalty.contact.stiffness = stiffness;
  HapticSessionSettings settings = base;
  settings.method = method;
  settings.recordTicks = true;
  settings.realTime = false;
  const HapticSessionResult r = runHapticSession(scene, settings);
  StabilityRun run;
  run.stiffness = stiffness;
  run.maxPenetrationCells = r.summary.maxPenetrationCells;
  run.inserted = r.summary.inserted;
  run.cycleP50Ms = r.summary.simCycleP50Ms;
  const double period = 1.0 / scene.device.rateHz;
  const double speedLimit = criteria.maxSpeedFactor * scene.script.peakSpeed() + 0.01;
  const std::size_t tailStart =
      r.ticks.size() - std::min<std::size_t>(r.ticks.size(), std::size_t(criteria.tailSeconds / period));
  std::int64_t reversals = 0, tailTicks = 0;
  Vec3 lastVelocity = Vec3::Zero();
  bool finite = true;
  for (std::size_t i = 0; i < r.ticks.size(); ++i) {
    const HapticTickRecord& t = r.ticks[i];
    finite = finite && t.worldFromSimulation.matrix().allFinite();
    const Vec3 sim = t.worldFromSimulation.translation();
    run.maxSeparationCells =
        std::max(run.maxSeparationCells, (sim - t.worldFromDevice.translation()).norm() / scene.cellSize);
    if (i == 0) continue;
    const Vec3 v = (sim - r.ticks[i - 1].worldFromSimulation.translation()) / period;
    run.maxSpeed = std::max(run.maxSpeed, v.norm());
    if (i >= tailStart) {
      ++tailTicks;
      bool reversed = false;
      for (int a = 0; a < 3; ++a) reversed = reversed || (v[a] * lastVelocity[a] < 0.0 && std::abs(v[a]) > 1e-3);
      reversals += reversed;
    }
    lastVelocity = v;
  }
  run.reversalFraction = tailTicks > 0 ? double(reversals) / double(tailTicks) : 0.0;
  if (!r.summary.error.empty())
    run.reason = "error: " + r.summary.error;
  else if (!r.summary.runaway.empty())
    run.reason = "runaway: " + r.summary.runaway;
  else if (!finite)
    run.reason = "non-finite state";
  else if (run.maxSeparationCells > criteria.maxSeparationCells)
    run.reason = describe("ejected: separation (cells)", run.maxSeparationCells, criteria.maxSeparationCells);
  else if (run.maxSpeed > speedLimit)
    run.reason = describe("speed (m/s)", run.maxSpeed, speedLimit);
  else if (run.maxPenetrationCells > criteria.maxPenetrationCells)
    run.reason = describe("penetration (cells)", run.maxPenetrationCells, criteria.maxPenetrationCells);
  else if (run.reversalFraction > criteria.maxReversalFraction)
    run.reason = describe("chatter: velocity reversals per tick", run.reversalFraction, criteria.maxReversalFraction);
  run.stable = run.reason.empty();
  return run;
}

StabilitySweep sweepStiffness(const HapticScene& scene, HapticMethod method, double lowest, double highest,
                              double factor, const StabilityCriteria& criteria, const HapticSessionSettings& base) {
  if (!(lowest > 0.0) || !(highest >= lowest) || !(factor > 1.0) || !std::isfinite(highest))
    throw Error("stability sweep: need 0 < lowest <= highest and factor > 1");
  StabilitySweep sweep;
  int unstableInARow = 0;
  double lastStable = 0.0;
  for (double k = lowest; k <= highest * (1.0 + 1e-9); k *= factor) {
    sweep.runs.push_back(runAtStiffness(scene, method, k, criteria, base));
    if (sweep.runs.back().stable) {
      lastStable = k;
      unstableInARow = 0;
      continue;
    }
    ++sweep.isolatedFailures;
    if (++unstableInARow == 2) {
      sweep.isolatedFailures -= 2;  // the pair that ends the sweep is the limit, not isolated
      sweep.foundLimit = true;
      break;
    }
  }
  if (!sweep.foundLimit && unstableInARow == 1) {
    // The ladder ended on a failure: it counts as the limit.
    --sweep.isolatedFailures;
    sweep.foundLimit = true;
  }
  sweep.maxStableStiffness = lastStable;
  return sweep;
}

}  // namespace sdfccd::haptics
