/// @file
/// @brief The paper's Fig. 10b experiment: the largest contact stiffness at which penalty haptic rendering of a
/// scene stays stable, for the continuous and the discrete penalty model (same timestep, same scripted user).
///
/// @details One run is a virtual-time session of the scene with the penalty stiffness per point set to k. It is
/// called unstable when any of these happens (each is what "unstable" looks like in the peg: the object is thrown
/// out of the hole, or buzzes against the wall):
///   - the session stops (runaway guard) or fails, or the state is not finite;
///   - the simulated object gets farther than `maxSeparationCells` field cells from the device (ejected: the
///     saturated coupling cannot hold it);
///   - the object's speed exceeds `maxSpeedFactor` times the scripted user's peak speed plus 1 cm/s;
///   - the penetration exceeds `maxPenetrationCells`;
///   - chatter: over the last `tailSeconds` of the run the object's velocity changes sign along some axis in more
///     than `maxReversalFraction` of the ticks while moving faster than 1 mm/s (a stable object slides or rests).
/// The sweep walks k up a geometric ladder until two rungs in a row are unstable and returns the last stable k below
/// them. Why two: in the peg, stability is not monotone in k (e.g. the continuous model fails at 7.9e6 N/m, is
/// stable from 1e7 to 1.6e7 and fails from 2e7 on; the discrete one fails at 1.6e7 and is stable at 2e7 and 2.5e7):
/// a failure is a rare event of one trajectory (a line of points hitting a wall in one tick), so a single unstable
/// rung is counted as isolated (isolatedFailures) and the sweep goes on.
#pragma once

#include <string>
#include <vector>

#include "sdfccd/haptics/haptic_session.h"

namespace sdfccd::haptics {

struct StabilityCriteria {
  double maxSeparationCells = 6.0;
  double maxSpeedFactor = 5.0;
  double maxPenetrationCells = 2.0;
  double tailSeconds = 0.4;
  double maxReversalFraction = 0.2;
};

/// One run at one stiffness.
struct StabilityRun {
  double stiffness = 0.0;  ///< N/m per point
  bool stable = false;
  std::string reason;  ///< why not ("" when stable)
  double maxSeparationCells = 0.0;
  double maxSpeed = 0.0;  ///< m/s
  double maxPenetrationCells = 0.0;
  double reversalFraction = 0.0;
  bool inserted = false;
  double cycleP50Ms = 0.0;
};

/// Runs `scene` once with penalty stiffness `stiffness` (method Penalty or DiscretePenalty).
StabilityRun runAtStiffness(const HapticScene& scene, HapticMethod method, double stiffness,
                            const StabilityCriteria& criteria = {}, const HapticSessionSettings& base = {});

struct StabilitySweep {
  std::vector<StabilityRun> runs;   ///< in ladder order, up to and including the two unstable rungs that end it
  double maxStableStiffness = 0.0;  ///< the last stable rung below them (0: none)
  bool foundLimit = false;          ///< false: no two unstable rungs in a row up to `highest`
  int isolatedFailures = 0;         ///< unstable rungs below the limit, each followed by a stable one
};

/// Walks k = lowest * factor^i up to `highest` and stops after two unstable rungs in a row. Throws sdfccd::Error on bad
/// arguments.
StabilitySweep sweepStiffness(const HapticScene& scene, HapticMethod method, double lowest, double highest,
                              double factor, const StabilityCriteria& criteria = {},
                              const HapticSessionSettings& base = {});

}  // namespace sdfccd::haptics
