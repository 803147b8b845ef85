/// @file
/// @brief runHapticSession: a scripted, headless haptics session of one scene with one rendering method
/// (paper Sections 4.1, 4.2 and 5).
///
/// @details The emulated device runs the haptic loop at its rate. Per method:
/// - Constraint / DiscreteConstraint (Section 4.2): two asynchronous loops, as in the paper. The haptic loop
///   publishes the device pose and renders the newest F_c; the simulation loop (QP + CCD) runs as fast as it
///   can on its own thread, reading the newest device pose and publishing F_c, its pose and its contacts.
///   They share two LatestValue slots (latest_value.h) and nothing else. When the god-object has settled
///   and the device pose has not changed, the simulation loop yields its core instead of spinning.
/// - Penalty / DiscretePenalty (Section 4.1): the implicit penalty step runs inside the haptic loop (one
///   simulation step per haptic tick, as the paper's admittance-mode loop does).
/// Real time: the device loop sleeps to its deadlines on its own thread (start()). Virtual time
/// (realTime = false, for tests): the same ticks back to back, and the constraint method runs
/// `simCyclesPerTick` simulation cycles in lockstep inside each tick, so a run is deterministic.
///
/// The loops run on TwoLoopRunner (two_loop_runner.h) with the scene's emulated device or the caller's HapticDevice;
/// every wrench goes through the device port's PassivityController (passivity.h: energy observer, force-rate limit,
/// energy-bounding controller; the observer alone when passivityEnabled is false). An exception in a loop ends the
/// session with summary.error set and the device rendering zero, instead of terminating the process.
///
/// Contacts: both methods take them from the scene's one contact source (ObstacleContacts, haptic_obstacles.h): the
/// single static object as an obstacle with a fixed pose, or the scene's "obstacles", each simulation step told the
/// device tick's time so moving obstacles are where their path puts them; penetration is the deepest over every pair.
/// The stages of the haptic tick and of the simulation cycle are listed in src/session/session_stages.h.
///
/// Penetration is measured after each simulation step over every shell point (a point query of the tree at
/// phi <= 0), outside the timed part of the cycle.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdfccd/haptics/haptic_scene.h"
#include "sdfccd/haptics/passivity.h"

namespace sdfccd::haptics {

enum class HapticMethod { Penalty, DiscretePenalty, Constraint, DiscreteConstraint };

/// "penalty", "discrete-penalty", "constraint", "discrete-constraint".
const char* toString(HapticMethod method);
/// Parses the names above. Throws sdfccd::Error on another name.
HapticMethod parseHapticMethod(const std::string& name);

struct HapticSessionSettings {
  HapticMethod method = HapticMethod::Constraint;
  double seconds = 0.0;      ///< s; 0: the scene's default
  bool realTime = false;     ///< true: 1 kHz loop on its own thread + simulation thread
  int simCyclesPerTick = 1;  ///< virtual time, constraint methods: simulation cycles per haptic tick
  bool recordTicks = true;   ///< keep one HapticTickRecord per tick
  int ccdThreads = 1;        ///< CCD worker threads of the simulation
  /// Real time only, opt-in: ask for SCHED_FIFO for the haptic loop (the summary says whether it was granted).
  bool realTimePriority = false;
  /// The passivity observer/controller and force-rate limit on the device port (passivity.h); the device's own
  /// force and torque limits are added to `passivity`.
  bool passivityEnabled = true;
  PassivitySettings passivity = defaultSessionPassivity();

  /// The session's default: observer on, force change at most 1 N and torque change at most 0.05 N m per tick.
  static PassivitySettings defaultSessionPassivity() {
    PassivitySettings p;
    p.maxForceStep = 1.0;
    p.maxTorqueStep = 0.05;
    return p;
  }
};

/// One row of the per-tick log (written by the haptic loop).
struct HapticTickRecord {
  std::int64_t tick = 0;
  double time = 0.0;  ///< s
  Rigid worldFromDevice = Rigid::Identity();
  Rigid worldFromSimulation = Rigid::Identity();  ///< god-object or penalty object (newest known)
  Vec6 wrenchOnDevice = Vec6::Zero();             ///< N, N m (before the device's clamping)
  int contacts = 0;
  double penetration = 0.0;  ///< model units, >= 0, newest known
  int qpState = 0;           ///< ContactQpState of the newest cycle (constraint methods)
  double simCycleMs = 0.0;   ///< ms, duration of the newest simulation cycle
};

struct HapticSessionSummary {
  std::string scene;
  /// The scene file, absolute (summary "scene_file", for `sdfccd render`/`plot` of a run folder); "" = not
  /// written (sessions run from a scene in memory).
  std::string sceneFile;
  std::string method;
  bool realTime = false;
  double seconds = 0.0;
  bool hasInsertCheck = false;
  bool inserted = false;
  double maxPenetrationCells = 0.0;
  bool hasTunnelCheck = false;
  bool tunneled = false;
  double hapticRateHz = 0.0;
  std::int64_t hapticTicks = 0;
  std::int64_t hapticOverruns = 0;
  double hapticJitterP99Us = 0.0;
  std::int64_t simCycles = 0;
  double simCycleP50Ms = 0.0;
  double simCycleP99Ms = 0.0;
  double simCycleMaxMs = 0.0;
  double simCycleCpuP50Ms = 0.0;  ///< the simulation thread's CPU time per cycle (without preemption)
  double simCycleCpuP99Ms = 0.0;
  int maxContacts = 0;
  double meanContacts = 0.0;       ///< over simulation cycles
  std::int64_t stuckCycles = 0;    ///< constraint: cycles whose QP reported Stuck, or pinched by moving obstacles
  std::int64_t failedCycles = 0;   ///< constraint: cycles whose QP failed
  std::int64_t blockedCycles = 0;  ///< constraint: cycles whose QP optimum was ~0
  int shellPoints = 0;
  Vec3 finalPosition = Vec3::Zero();  ///< the simulated object's centre at the end
  double insertProgress = 0.0;        ///< deepest reach along the insert axis (model units)
  /// The runaway guard (scene key "guard"): its first violation, one line naming the body ("" if none), and
  /// whether it stopped the session (action "stop": the device rendered zero force from that tick on and the loop
  /// ended; hapticTicks counts the ticks run).
  std::string runaway;
  bool guardStopped = false;
  /// An exception in the haptic or the simulation loop ended the session (one line naming the loop; "" if none): the
  /// device rendered zero from that tick on and the loops were joined.
  std::string error;
  std::string realTimePriority = "off";  ///< "off", "granted (SCHED_FIFO 80)" or "denied (...): reason"
  bool passivityEnabled = false;
  PassivityStats passivity;          ///< the device port's energy account (passivity.h)
  double colgateMaxStiffness = 0.0;  ///< N/m, 2 b / T of the emulated device (b: friction + hand damping)
};

struct HapticSessionResult {
  HapticSessionSummary summary;
  std::vector<HapticTickRecord> ticks;
};

/// Runs the session on the scene's emulated device. Throws sdfccd::Error on bad settings; an exception inside a
/// loop does not throw: it ends the session with summary.error set (the device rendering zero).
HapticSessionResult runHapticSession(const HapticScene& scene, const HapticSessionSettings& settings);
/// The same on the caller's device (a lab's device, a TrajectoryPlayer, an emulator of its own), at the scene's
/// device rate (else sdfccd::Error). The session ends after its seconds or when the device runs out.
HapticSessionResult runHapticSession(const HapticScene& scene, const HapticSessionSettings& settings,
                                     HapticDevice& device);

}  // namespace sdfccd::haptics
