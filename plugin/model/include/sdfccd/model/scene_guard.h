/// @file
/// @brief SceneGuard: the limits of the runaway watchdog (key "guard" of a scene file; docs/scene-format.md).
#pragma once

namespace sdfccd {

/// What a run does when its state leaves the physical bounds (RunawayGuard, runaway_guard.h).
enum class GuardAction {
  Stop,    ///< one line on stderr naming the body, exit code 3 (`sdfccd simulate`)
  Report,  ///< the run goes on; the first violation is kept in summary.json (stability searches)
  Off,     ///< no checks
};

/// The runaway watchdog's limits. Generous by design: a sound run stays orders of magnitude inside them, an
/// exploded one (1e9 J and more on a resting box) leaves them within a few frames.
struct SceneGuard {
  /// "energy_factor": kinetic energy may reach this many times the scene's energy budget (initial kinetic plus
  /// potential energy above the lowest point, plus the work gravity and kinematic bodies can do; runaway_guard.h).
  double energyFactor = 1000.0;
  /// "max_speed" (m/s): a body may move this much faster than its start speed, gravity and the kinematic bodies
  /// could make it.
  double maxSpeed = 1000.0;
  /// "extent_factor": a body may go this many times the scene's initial extent from the origin (plus the
  /// distance its start speed, gravity and the kinematic bodies could carry it).
  double extentFactor = 1000.0;
  GuardAction action = GuardAction::Stop;  ///< "action": stop, report or off
};

}  // namespace sdfccd
