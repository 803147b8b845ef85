/// @file
/// @brief runHapticSession: the haptic loop, the simulation loop and what they record.
#include "sdfccd/haptics/haptic_session.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <thread>

#include "sdfccd/error.h"
#include "sdfccd/haptics/latest_value.h"
#include "sdfccd/haptics/two_loop_runner.h"
#include "sdfccd/thread_cpu_time.h"
#include "session_guard.h"

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

using Clock = std::chrono::steady_clock;

/// Deepest penetration (phi < 0) over every shell point at a pose: a point query of the tree.
template <class Field>
double measurePenetration(const PointTree& tree, const Field& field, const Rigid& sdfFromBody,
                          RigidCcdResult& scratch) {
  RigidCcdSettings s;
  s.sigma = 0.0;
  s.mode = CcdMode::FirstHit;
  s.octree = OctreeMode::Leaves;
  rigidCcd(tree, field, sdfFromBody, sdfFromBody, s, scratch);
  double deepest = 0.0;
  for (const PointContact& c : scratch.contacts) deepest = std::max(deepest, -c.depthAtEnd);
  return deepest;
}

/// What the simulation publishes for the haptic loop.
struct SimulationOutput {
  Vec6 wrenchOnDevice = Vec6::Zero();
  Rigid worldFromSimulation = Rigid::Identity();
  int contacts = 0;
  double penetration = 0.0;
  int qpState = 0;
  double cycleMs = 0.0;
  bool idle = false;  // the cycle moved nothing (device still, god-object settled)
};

/// Statistics kept by whichever thread runs the simulation.
struct SimulationLog {
  std::vector<double> cycleMs;
  std::vector<double> cycleCpuMs;
  int maxContacts = 0;
  double contactSum = 0.0;
  double maxPenetration = 0.0;
  std::int64_t stuck = 0, failed = 0, blocked = 0;
  bool inserted = false;
  bool tunneled = false;
  double insertProgress = -1e300;

  void observe(const HapticScene& scene, const Rigid& pose, int contacts, double penetration) {
    maxContacts = std::max(maxContacts, contacts);
    contactSum += contacts;
    maxPenetration = std::max(maxPenetration, penetration);
    const Vec3 c = pose.translation();
    if (scene.checks.hasInsert) {
      const double reach = scene.checks.insertAxis.dot(c);
      insertProgress = std::max(insertProgress, reach);
      if (reach >= scene.checks.insertDepth) inserted = true;
    }
    if (scene.checks.hasTunnel && scene.checks.tunnelNormal.dot(c) > scene.checks.tunnelOffset) tunneled = true;
  }
};

/// The session against one static field (`field`), or against the scene's obstacles (`obstacles` set; `Field` then
/// unused).
template <class Field>
HapticSessionResult runWithField(const HapticScene& scene, const Field* field, ObstacleContacts* obstacles,
                                 const HapticSessionSettings& settings, HapticDevice* externalDevice) {
  const double seconds = settings.seconds > 0.0 ? settings.seconds : scene.seconds;
  if (!(seconds > 0.0) || !std::isfinite(seconds) || seconds > 3600.0)
    throw Error("session: seconds must be in (0, 3600]");
  if (settings.simCyclesPerTick < 1 || settings.simCyclesPerTick > 1000)
    throw Error("session: simCyclesPerTick must be in [1, 1000]");
  if (settings.realTimePriority && !settings.realTime) throw Error("session: realTimePriority needs realTime");
  const std::int64_t ticks = static_cast<std::int64_t>(std::llround(seconds * scene.device.rateHz));
  const PointTree& tree = *scene.tree;
  const bool constraint =
      settings.method == HapticMethod::Constraint || settings.method == HapticMethod::DiscreteConstraint;

  std::optional<DeviceEmulator> emulator;  // the scene's emulated device, unless the caller brought one
  HapticDevice& device =
      externalDevice ? *externalDevice : emulator.emplace(scene.device, scene.script, scene.worldFromBodyStart);
  HapticSessionResult result;
  if (settings.recordTicks) result.ticks.reserve(static_cast<std::size_t>(ticks));
  SimulationLog log;
  LatestValue<Rigid> devicePose;
  LatestValue<SimulationOutput> simulationOutput;
  RigidCcdResult penetrationScratch;

  const auto record = [&](const DeviceState& state, const SimulationOutput& sim) {
    if (!settings.recordTicks) return;
    HapticTickRecord row;
    row.tick = state.tick;
    row.time = state.time;
    row.worldFromDevice = state.body.worldFromBody;
    row.worldFromSimulation = sim.worldFromSimulation;
    row.wrenchOnDevice = sim.wrenchOnDevice;
    row.contacts = sim.contacts;
    row.penetration = sim.penetration;
    row.qpState = sim.qpState;
    row.simCycleMs = sim.cycleMs;
    result.ticks.push_back(row);
  };

  // The end of every haptic tick: records it and returns the wrench to render, zero once the guard has stopped
  // the session (and the loop is asked to stop after this tick).
  SessionGuard guard(scene);
  // Without passivity the observer still keeps the port's energy account (summary), acting on nothing.
  PassivitySettings passivitySettings = settings.passivityEnabled ? settings.passivity : PassivitySettings{};
  passivitySettings.controller = settings.passivityEnabled && passivitySettings.controller;
  passivitySettings.maxForce = std::min(passivitySettings.maxForce, scene.device.maxForce);
  passivitySettings.maxTorque = std::min(passivitySettings.maxTorque, scene.device.maxTorque);
  PassivityController passivity(passivitySettings);
  TwoLoopRunner* runnerForStop = nullptr;  // set once the runner exists (the handler runs only inside it)
  const auto guarded = [&](const DeviceState& state, SimulationOutput sim, bool stop) {
    if (stop) {
      sim.wrenchOnDevice = Vec6::Zero();
      runnerForStop->requestStop();
    } else {
      sim.wrenchOnDevice = passivity.filter(state, sim.wrenchOnDevice);
    }
    record(state, sim);
    return sim.wrenchOnDevice;
  };

  const Rigid sdfFromWorld = scene.worldFromSdf.inverse();
  // A moving obstacle keeps the simulation busy even while the device and the god-object are still.
  const bool movingObstacles = std::any_of(scene.obstacles.begin(), scene.obstacles.end(),
                                           [](const HapticObstacle& o) { return o.path.moving(); });
  // One simulation step, `step()`, with its thread CPU time and wall time (ms) logged; returns its result.
  const auto timedStep = [&](const auto& step) {
    const double cpu0 = threadCpuSeconds();
    const auto t0 = Clock::now();
    auto r = step();
    const auto t1 = Clock::now();
    log.cycleCpuMs.push_back(1e3 * (threadCpuSeconds() - cpu0));
    log.cycleMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    return r;
  };
  // What a step hands the haptic loop (its time is the last logged), observed by the log: the wrench, the pose
  // reached, its contacts and the penetration measured there (untimed).
  const auto stepOutput = [&](const Vec6& wrenchOnDevice, const Rigid& worldFromSimulation, int contacts) {
    SimulationOutput out;
    out.cycleMs = log.cycleMs.back();
    out.wrenchOnDevice = wrenchOnDevice;
    out.worldFromSimulation = worldFromSimulation;
    out.contacts = contacts;
    out.penetration = obstacles
                          ? obstacles->penetration(worldFromSimulation)
                          : measurePenetration(tree, *field, sdfFromWorld * worldFromSimulation, penetrationScratch);
    log.observe(scene, worldFromSimulation, contacts, out.penetration);
    return out;
  };

  // The two loops: the constraint methods simulate in their own loop; the penalty step runs inside the haptic tick.
  TwoLoopSettings loopSettings;
  loopSettings.ticks = ticks;
  loopSettings.realTime = settings.realTime;
  loopSettings.simCyclesPerTick = constraint ? settings.simCyclesPerTick : 1;
  loopSettings.loop.realTimePriority = settings.realTimePriority;
  TwoLoopRunner runner(device, loopSettings);
  runnerForStop = &runner;
  TwoLoopResult loops;
  if (constraint) {
    GodObjectSettings godSettings = scene.god;
    godSettings.continuous = settings.method == HapticMethod::Constraint;
    godSettings.threads = settings.ccdThreads;
    std::optional<GodObject<Field>> godSlot;
    if (obstacles)
      godSlot.emplace(tree, *obstacles, scene.worldFromBodyStart, godSettings);
    else
      godSlot.emplace(tree, *field, scene.worldFromSdf, scene.worldFromBodyStart, godSettings);
    GodObject<Field>& god = *godSlot;
    // One simulation cycle: the timed QP + CCD, then the (untimed) penetration measurement.
    const auto cycle = [&](const Rigid& worldFromDevice, double time) {
      god.setObstacleTime(time);
      const GodObjectStepResult r = timedStep([&] { return god.step(worldFromDevice); });
      SimulationOutput out = stepOutput(r.wrenchOnDevice, god.pose(), r.nextContactCount);
      out.qpState = static_cast<int>(r.qpState);
      out.idle = r.fraction * r.constrained.norm() < 1e-9 * scene.cellSize && !movingObstacles;
      log.stuck += r.qpState == ContactQpState::Stuck || r.squeezed;
      log.failed += r.qpState == ContactQpState::Failed;
      log.blocked += r.blocked;
      return out;
    };
    SimulationOutput initial;
    initial.worldFromSimulation = scene.worldFromBodyStart;
    simulationOutput.publish(initial);
    const SimulationCycle simulate = [&](const DeviceState& state) {
      if (settings.faultInjection.simulationCycle >= 0 &&
          static_cast<std::int64_t>(log.cycleMs.size()) >= settings.faultInjection.simulationCycle)
        throw Error("injected fault at simulation cycle " + std::to_string(log.cycleMs.size()));
      const SimulationOutput out = cycle(state.body.worldFromBody, state.time);
      simulationOutput.publish(out);
      return !out.idle;
    };
    loops = runner.run(simulate, [&](const DeviceState& state) {
      SimulationOutput sim;
      simulationOutput.read(sim);
      return guarded(state, sim, guard.observePose(state.time, sim.worldFromSimulation));
    });
    result.summary.finalPosition = god.pose().translation();
  } else {
    PenaltyRendererSettings penaltySettings = scene.penalty;
    penaltySettings.contact.model =
        settings.method == HapticMethod::Penalty ? PenaltyModel::Continuous : PenaltyModel::Discrete;
    penaltySettings.timestep = 1.0 / scene.device.rateHz;
    penaltySettings.threads = settings.ccdThreads;
    std::optional<PenaltyRenderer<Field>> rendererSlot;
    if (obstacles)
      rendererSlot.emplace(tree, *obstacles, scene.worldFromBodyStart, penaltySettings);
    else
      rendererSlot.emplace(tree, *field, scene.worldFromSdf, scene.worldFromBodyStart, penaltySettings);
    PenaltyRenderer<Field>& renderer = *rendererSlot;
    // The penalty step runs in the haptic loop itself (one step per tick).
    loops = runner.run(nullptr, [&](const DeviceState& state) {
      if (settings.faultInjection.hapticTick >= 0 && state.tick >= settings.faultInjection.hapticTick)
        throw Error("injected fault at haptic tick " + std::to_string(state.tick));
      renderer.setObstacleTime(state.time);
      const PenaltyStepResult r = timedStep([&] { return renderer.step(state.body); });
      const SimulationOutput sim = stepOutput(r.wrenchOnDevice, renderer.state().worldFromBody, r.contactCount);
      return guarded(state, sim, guard.observeState(state.time, renderer.state()));
    });
    result.summary.finalPosition = renderer.state().worldFromBody.translation();
  }
  const LoopTimingStats& timing = loops.timing;

  HapticSessionSummary& s = result.summary;
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
  s.shellPoints = tree.pointCount();
  s.runaway = guard.violation();
  s.guardStopped = guard.stopped();
  s.error = loops.error;
  s.realTimePriority = timing.realTimePriority;
  s.passivityEnabled = settings.passivityEnabled;
  s.passivity = passivity.stats();
  s.colgateMaxStiffness =
      colgateMaxStiffness(scene.device.linearFriction + scene.device.userDamping, 1.0 / scene.device.rateHz);
  return result;
}

}  // namespace

namespace {

HapticSessionResult runOn(const HapticScene& scene, const HapticSessionSettings& settings, HapticDevice* device) {
  if (!scene.tree) throw Error("session: the scene has no shell");
  if (!scene.obstacles.empty()) {
    ObstacleContacts obstacles(scene.obstacles, *scene.tree, scene.toolField.get());
    return runWithField<GridField>(scene, nullptr, &obstacles, settings, device);
  }
  if (scene.plane) return runWithField(scene, &*scene.plane, nullptr, settings, device);
  if (!scene.grid) throw Error("session: the scene has no static object");
  return runWithField(scene, scene.grid.get(), nullptr, settings, device);
}

}  // namespace

HapticSessionResult runHapticSession(const HapticScene& scene, const HapticSessionSettings& settings) {
  return runOn(scene, settings, nullptr);
}

HapticSessionResult runHapticSession(const HapticScene& scene, const HapticSessionSettings& settings,
                                     HapticDevice& device) {
  if (std::abs(device.rateHz() - scene.device.rateHz) > 1e-9 * scene.device.rateHz)
    throw Error("session: the device's rate differs from the scene's device rate");
  return runOn(scene, settings, &device);
}

}  // namespace sdfccd::haptics
