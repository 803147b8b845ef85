/// @file
/// @brief runHapticSession: the scene's contact source, the renderer of the method, the two loops and the summary
/// (the loops' stages are in session_stages.h).
#include "sdfccd/haptics/haptic_session.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "sdfccd/error.h"
#include "session/fault_injection.h"
#include "session/session_stages.h"

namespace sdfccd::haptics {

const char* toString(HapticMethod method) {
  switch (method) {
    case HapticMethod::Penalty:
      return "penalty";
    case HapticMethod::DiscretePenalty:
      return "discrete-penalty";
    case HapticMethod::Constraint:
      return "constraint";
    case HapticMethod::DiscreteConstraint:
      return "discrete-constraint";
  }
  return "?";
}

HapticMethod parseHapticMethod(const std::string& name) {
  for (HapticMethod m : {HapticMethod::Penalty, HapticMethod::DiscretePenalty, HapticMethod::Constraint,
                         HapticMethod::DiscreteConstraint}) {
    if (name == toString(m)) return m;
  }
  throw Error("unknown haptic method '" + name + "' (penalty, discrete-penalty, constraint, discrete-constraint)");
}

namespace {

bool isConstraint(HapticMethod method) {
  return method == HapticMethod::Constraint || method == HapticMethod::DiscreteConstraint;
}

/// The scene's one contact source: its obstacles, or its single static object as an obstacle with a fixed pose.
ObstacleContacts sceneContacts(const HapticScene& scene) {
  if (!scene.obstacles.empty()) return ObstacleContacts(scene.obstacles, *scene.tree, scene.toolField.get());
  if (scene.plane) return ObstacleContacts(*scene.tree, *scene.plane, scene.worldFromSdf);
  if (!scene.grid) throw Error("session: the scene has no static object");
  return ObstacleContacts(*scene.tree, *scene.grid, scene.worldFromSdf);
}

/// The session's length (s), checked with the other settings. Throws sdfccd::Error on bad settings.
double checkedSeconds(const HapticScene& scene, const HapticSessionSettings& settings) {
  const double seconds = settings.seconds > 0.0 ? settings.seconds : scene.seconds;
  if (!(seconds > 0.0) || !std::isfinite(seconds) || seconds > 3600.0)
    throw Error("session: seconds must be in (0, 3600]");
  if (settings.simCyclesPerTick < 1 || settings.simCyclesPerTick > 1000)
    throw Error("session: simCyclesPerTick must be in [1, 1000]");
  if (settings.realTimePriority && !settings.realTime) throw Error("session: realTimePriority needs realTime");
  return seconds;
}

/// The constraint methods: the god-object's simulation loop beside the haptic loop. Returns the loops' result and
/// the god-object's final position.
std::pair<TwoLoopResult, Vec3> runConstraint(const HapticScene& scene, const HapticSessionSettings& settings,
                                             const SessionFaults& faults, ObstacleContacts contacts,
                                             TwoLoopRunner& runner, SimulationLog& log, DevicePort& port) {
  GodObjectSettings godSettings = scene.god;
  godSettings.continuous = settings.method == HapticMethod::Constraint;
  godSettings.threads = settings.ccdThreads;
  GodObject god(std::move(contacts), scene.worldFromBodyStart, godSettings);
  ConstraintLoops loops(scene, faults, god, log, port);
  const TwoLoopResult result = runner.run([&](const DeviceState& device) { return loops.simulationCycle(device); },
                                          [&](const DeviceState& state) { return loops.hapticTick(state); });
  return {result, god.pose().translation()};
}

/// The penalty methods: the penalty step inside the haptic tick.
std::pair<TwoLoopResult, Vec3> runPenalty(const HapticScene& scene, const HapticSessionSettings& settings,
                                          const SessionFaults& faults, ObstacleContacts contacts, TwoLoopRunner& runner,
                                          SimulationLog& log, DevicePort& port) {
  PenaltyRendererSettings penaltySettings = scene.penalty;
  penaltySettings.contact.model =
      settings.method == HapticMethod::Penalty ? PenaltyModel::Continuous : PenaltyModel::Discrete;
  penaltySettings.timestep = 1.0 / scene.device.rateHz;
  penaltySettings.threads = settings.ccdThreads;
  PenaltyRenderer renderer(std::move(contacts), scene.worldFromBodyStart, penaltySettings);
  PenaltyLoop loop(scene, faults, renderer, log, port);
  const TwoLoopResult result = runner.run(nullptr, [&](const DeviceState& state) { return loop.hapticTick(state); });
  return {result, renderer.state().worldFromBody.translation()};
}

/// The summary of a finished session.
HapticSessionSummary summarize(const HapticScene& scene, const HapticSessionSettings& settings, double seconds,
                               const TwoLoopResult& loops, const SimulationLog& log, const DevicePort& port) {
  const LoopTimingStats& timing = loops.timing;
  HapticSessionSummary s;
  s.scene = scene.name;
  s.method = toString(settings.method);
  s.realTime = settings.realTime;
  s.seconds = seconds;
  s.hasInsertCheck = scene.checks.hasInsert;
  s.inserted = log.inserted;
  s.insertProgress = scene.checks.hasInsert ? log.insertProgress : 0.0;
  s.maxPenetrationCells = log.maxPenetration / scene.cellSize;
  s.hasTunnelCheck = scene.checks.hasTunnel;
  s.tunneled = log.tunneled;
  s.hapticRateHz = timing.achievedRateHz;
  s.hapticTicks = timing.ticks;
  s.hapticOverruns = timing.overruns;
  s.hapticJitterP99Us = timing.jitterP99Us;
  s.simCycles = static_cast<std::int64_t>(log.cycleMs.size());
  s.simCycleP50Ms = percentile(log.cycleMs, 50.0);
  s.simCycleP99Ms = percentile(log.cycleMs, 99.0);
  s.simCycleMaxMs = log.cycleMs.empty() ? 0.0 : *std::max_element(log.cycleMs.begin(), log.cycleMs.end());
  s.simCycleCpuP50Ms = percentile(log.cycleCpuMs, 50.0);
  s.simCycleCpuP99Ms = percentile(log.cycleCpuMs, 99.0);
  s.maxContacts = log.maxContacts;
  s.meanContacts = log.cycleMs.empty() ? 0.0 : log.contactSum / static_cast<double>(log.cycleMs.size());
  s.stuckCycles = log.stuck;
  s.failedCycles = log.failed;
  s.blockedCycles = log.blocked;
  s.shellPoints = scene.tree->pointCount();
  s.runaway = port.guard().violation();
  s.guardStopped = port.guard().stopped();
  s.error = loops.error;
  s.realTimePriority = timing.realTimePriority;
  s.passivityEnabled = settings.passivityEnabled;
  s.passivity = port.passivity().stats();
  s.colgateMaxStiffness =
      colgateMaxStiffness(scene.device.linearFriction + scene.device.userDamping, 1.0 / scene.device.rateHz);
  return s;
}

/// The session on the scene's emulated device (`externalDevice` null) or the caller's.
HapticSessionResult run(const HapticScene& scene, const HapticSessionSettings& settings, HapticDevice* externalDevice,
                        const SessionFaults& faults) {
  if (!scene.tree) throw Error("session: the scene has no shell");
  ObstacleContacts contacts = sceneContacts(scene);
  const double seconds = checkedSeconds(scene, settings);
  const std::int64_t ticks = static_cast<std::int64_t>(std::llround(seconds * scene.device.rateHz));
  const bool constraint = isConstraint(settings.method);
  std::optional<DeviceEmulator> emulator;  // the scene's emulated device, unless the caller brought one
  HapticDevice& device =
      externalDevice ? *externalDevice : emulator.emplace(scene.device, scene.script, scene.worldFromBodyStart);
  HapticSessionResult result;
  if (settings.recordTicks) result.ticks.reserve(static_cast<std::size_t>(ticks));
  SimulationLog log;
  DevicePort port(scene, settings, result.ticks);
  TwoLoopSettings loopSettings;
  loopSettings.ticks = ticks;
  loopSettings.realTime = settings.realTime;
  loopSettings.simCyclesPerTick = constraint ? settings.simCyclesPerTick : 1;
  loopSettings.loop.realTimePriority = settings.realTimePriority;
  TwoLoopRunner runner(device, loopSettings);
  port.attach(runner);
  const auto [loops, finalPosition] =
      constraint ? runConstraint(scene, settings, faults, std::move(contacts), runner, log, port)
                 : runPenalty(scene, settings, faults, std::move(contacts), runner, log, port);
  result.summary = summarize(scene, settings, seconds, loops, log, port);
  result.summary.finalPosition = finalPosition;
  return result;
}

}  // namespace

HapticSessionResult runHapticSession(const HapticScene& scene, const HapticSessionSettings& settings) {
  return run(scene, settings, nullptr, SessionFaults{});
}

HapticSessionResult runHapticSession(const HapticScene& scene, const HapticSessionSettings& settings,
                                     HapticDevice& device) {
  return runHapticSessionWithFaults(scene, settings, device, SessionFaults{});
}

HapticSessionResult runHapticSessionWithFaults(const HapticScene& scene, const HapticSessionSettings& settings,
                                               HapticDevice& device, const SessionFaults& faults) {
  if (std::abs(device.rateHz() - scene.device.rateHz) > 1e-9 * scene.device.rateHz)
    throw Error("session: the device's rate differs from the scene's device rate");
  return run(scene, settings, &device, faults);
}

}  // namespace sdfccd::haptics
