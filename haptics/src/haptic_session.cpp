/// @file
/// @brief runHapticSession: the haptic loop, the simulation loop and what they record.
#include "sdfccd/haptics/haptic_session.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <thread>

#include "sdfccd/error.h"
#include "sdfccd/haptics/latest_value.h"
#include "sdfccd/haptics/two_loop_runner.h"
#include "sdfccd/model/runaway_guard.h"
#include "sdfccd/output_file.h"
#include "sdfccd/thread_cpu_time.h"

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

/// The fastest the scripted target moves (m/s): the largest distance between consecutive keys over their time.
double peakScriptSpeed(const UserScript& script) {
  double peak = 0.0;
  const std::vector<PoseKeyframe>& keys = script.keys();
  for (std::size_t i = 1; i < keys.size(); ++i) {
    const double dt = keys[i].time - keys[i - 1].time;
    const double d = (keys[i].worldFromTarget.translation() - keys[i - 1].worldFromTarget.translation()).norm();
    if (dt > 0.0) peak = std::max(peak, d / dt);
  }
  return peak;
}

/// A haptic scene as the runaway guard (sdfccd/model/runaway_guard.h) sees it: the simulated object, dynamic and at
/// rest at its start pose, and the user's hand as a kinematic body moving at the script's peak speed, so the guard
/// grants the object what a moving wall may give a body (twice the wall's speed). No gravity: haptic scenes have
/// none; the device's own force limit bounds the rest.
Scene guardScene(const HapticScene& scene) {
  Scene g;
  g.name = scene.name;
  g.guard = scene.guard;
  SceneBody object;
  object.name = "simulated object";
  object.mass = scene.mass;
  object.position = scene.worldFromBodyStart.translation();
  SceneBody hand;
  hand.name = "hand";
  hand.kinematic = true;
  hand.position = object.position;
  hand.velocity = Vec3(peakScriptSpeed(scene.script), 0.0, 0.0);
  g.bodies = {object, hand};
  return g;
}

/// The runaway watchdog of a session (issue 14): checks the simulated object's state on every haptic tick. On a
/// violation with action "stop" the tick renders zero force and the loop stops; with "report" the first violation
/// is kept and the session goes on. Used by the haptic loop's thread only.
class SessionGuard {
 public:
  explicit SessionGuard(const HapticScene& scene)
      : m_guard(guardScene(scene), 0.0),
        m_action(scene.guard.action),
        m_mass(scene.mass),
        m_inertiaDiagonal(scene.inertiaDiagonal),
        m_tick(1.0 / scene.device.rateHz),
        m_lastPose(scene.worldFromBodyStart) {}

  /// A body with velocities (the penalty renderer's object). True: stop the loop now.
  bool observeState(double time, const RigidBodyState& state) {
    return check(time, state.worldFromBody, state.linearVelocity, state.angularVelocity);
  }

  /// A quasi-static pose (the god-object): its velocity is the displacement since the pose last changed over the
  /// time since then (at least one tick), so a simulation loop that lags and then catches up is not a runaway.
  bool observePose(double time, const Rigid& pose) {
    Vec6 velocity = Vec6::Zero();
    if (!pose.isApprox(m_lastPose, 0.0)) {
      velocity = poseDifference(m_lastPose, pose) / std::max(m_tick, time - m_lastChange);
      m_lastPose = pose;
      m_lastChange = time;
    }
    return check(time, pose, velocity.head<3>(), velocity.tail<3>());
  }

  bool stopped() const { return m_stopped; }
  const std::string& violation() const { return m_violation; }  ///< the first one; "" if none

 private:
  bool check(double time, const Rigid& pose, const Vec3& velocity, const Vec3& angularVelocity) {
    if (m_action == GuardAction::Off || !m_violation.empty()) return m_stopped;
    GuardBodyState object{pose.translation(), velocity};
    GuardBodyState hand;  // the kinematic body is not checked
    double energy = 0.5 * m_mass * velocity.squaredNorm();
    if (pose.matrix().allFinite() && angularVelocity.allFinite()) {
      energy += 0.5 * angularVelocity.dot(worldInertia(pose, m_inertiaDiagonal) * angularVelocity);
    } else {
      object.position = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());  // reported as non-finite
    }
    const std::optional<std::string> v = m_guard.check(time, {object, hand}, energy);
    if (!v) return false;
    m_violation = *v;
    m_stopped = m_action == GuardAction::Stop;
    return m_stopped;
  }

  RunawayGuard m_guard;
  GuardAction m_action;
  double m_mass;
  Vec3 m_inertiaDiagonal;
  double m_tick;  ///< s
  Rigid m_lastPose;
  double m_lastChange = 0.0;  ///< s
  bool m_stopped = false;
  std::string m_violation;
};

template <class Field>
HapticSessionResult runWithField(const HapticScene& scene, const Field& field, const HapticSessionSettings& settings,
                                 HapticDevice* externalDevice) {
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
    out.penetration = measurePenetration(tree, field, sdfFromWorld * worldFromSimulation, penetrationScratch);
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
    GodObject<Field> god(tree, field, scene.worldFromSdf, scene.worldFromBodyStart, godSettings);
    // One simulation cycle: the timed QP + CCD, then the (untimed) penetration measurement.
    const auto cycle = [&](const Rigid& worldFromDevice) {
      const GodObjectStepResult r = timedStep([&] { return god.step(worldFromDevice); });
      SimulationOutput out = stepOutput(r.wrenchOnDevice, god.pose(), r.nextContactCount);
      out.qpState = static_cast<int>(r.qpState);
      out.idle = r.fraction * r.constrained.norm() < 1e-9 * scene.cellSize;
      log.stuck += r.qpState == ContactQpState::Stuck;
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
      const SimulationOutput out = cycle(state.body.worldFromBody);
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
    PenaltyRenderer<Field> renderer(tree, field, scene.worldFromSdf, scene.worldFromBodyStart, penaltySettings);
    // The penalty step runs in the haptic loop itself (one step per tick).
    loops = runner.run(nullptr, [&](const DeviceState& state) {
      if (settings.faultInjection.hapticTick >= 0 && state.tick >= settings.faultInjection.hapticTick)
        throw Error("injected fault at haptic tick " + std::to_string(state.tick));
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
  if (scene.plane) return runWithField(scene, *scene.plane, settings, device);
  if (!scene.grid) throw Error("session: the scene has no static object");
  return runWithField(scene, *scene.grid, settings, device);
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

void writeTickCsv(const std::string& path, const std::vector<HapticTickRecord>& ticks) {
  OutputFile file(path);
  std::ostream& out = file.stream();
  out << "tick,time,device_x,device_y,device_z,device_qw,device_qx,device_qy,device_qz,"
         "sim_x,sim_y,sim_z,sim_qw,sim_qx,sim_qy,sim_qz,force_x,force_y,force_z,torque_x,torque_y,torque_z,"
         "contacts,penetration,qp_state,sim_cycle_ms\n";
  out << std::setprecision(9);
  const auto pose = [&](const Rigid& r) {
    const Quat q(r.linear());
    out << r.translation().x() << ',' << r.translation().y() << ',' << r.translation().z() << ',' << q.w() << ','
        << q.x() << ',' << q.y() << ',' << q.z() << ',';
  };
  for (const HapticTickRecord& t : ticks) {
    out << t.tick << ',' << t.time << ',';
    pose(t.worldFromDevice);
    pose(t.worldFromSimulation);
    for (int i = 0; i < 6; ++i) out << t.wrenchOnDevice[i] << ',';
    out << t.contacts << ',' << t.penetration << ',' << t.qpState << ',' << t.simCycleMs << '\n';
  }
  file.commit();
}

namespace {

/// `text` as a JSON string literal (quotes, backslashes and control characters escaped).
std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned char>(c));
      out += escaped;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace

std::string summaryJson(const HapticSessionSummary& s) {
  std::ostringstream o;
  o << std::setprecision(9) << std::boolalpha;
  const auto num = [](double v) {
    std::ostringstream n;
    n << std::setprecision(9);
    if (std::isfinite(v))
      n << v;
    else
      n << "null";
    return n.str();
  };
  o << "{\n"
    << "  \"scene\": \"" << s.scene << "\",\n"
    << (s.sceneFile.empty() ? std::string() : "  \"scene_file\": " + jsonString(s.sceneFile) + ",\n")
    << "  \"method\": \"" << s.method << "\",\n"
    << "  \"real_time\": " << s.realTime << ",\n"
    << "  \"seconds\": " << num(s.seconds) << ",\n"
    << "  \"inserted\": " << (s.hasInsertCheck ? (s.inserted ? "true" : "false") : "null") << ",\n"
    << "  \"insert_progress\": " << num(s.insertProgress) << ",\n"
    << "  \"max_penetration_cells\": " << num(s.maxPenetrationCells) << ",\n"
    << "  \"tunneled\": " << (s.hasTunnelCheck ? (s.tunneled ? "true" : "false") : "null") << ",\n"
    << "  \"haptic_rate_hz\": " << num(s.hapticRateHz) << ",\n"
    << "  \"haptic_ticks\": " << s.hapticTicks << ",\n"
    << "  \"haptic_overruns\": " << s.hapticOverruns << ",\n"
    << "  \"haptic_jitter_p99_us\": " << num(s.hapticJitterP99Us) << ",\n"
    << "  \"sim_cycles\": " << s.simCycles << ",\n"
    << "  \"sim_cycle_p50_ms\": " << num(s.simCycleP50Ms) << ",\n"
    << "  \"sim_cycle_p99_ms\": " << num(s.simCycleP99Ms) << ",\n"
    << "  \"sim_cycle_max_ms\": " << num(s.simCycleMaxMs) << ",\n"
    << "  \"sim_cycle_cpu_p50_ms\": " << num(s.simCycleCpuP50Ms) << ",\n"
    << "  \"sim_cycle_cpu_p99_ms\": " << num(s.simCycleCpuP99Ms) << ",\n"
    << "  \"max_contacts\": " << s.maxContacts << ",\n"
    << "  \"mean_contacts\": " << num(s.meanContacts) << ",\n"
    << "  \"stuck_cycles\": " << s.stuckCycles << ",\n"
    << "  \"failed_cycles\": " << s.failedCycles << ",\n"
    << "  \"blocked_cycles\": " << s.blockedCycles << ",\n"
    << "  \"shell_points\": " << s.shellPoints << ",\n"
    << "  \"guard_stopped\": " << s.guardStopped << ",\n"
    << "  \"error\": " << (s.error.empty() ? std::string("null") : jsonString(s.error)) << ",\n"
    << "  \"real_time_priority\": " << jsonString(s.realTimePriority) << ",\n"
    << "  \"passivity\": " << s.passivityEnabled << ",\n"
    << "  \"port_energy_j\": " << num(s.passivity.energy) << ",\n"
    << "  \"port_energy_min_j\": " << num(s.passivity.minEnergy) << ",\n"
    << "  \"port_deficit_bound_j\": " << num(s.passivity.deficitBound) << ",\n"
    << "  \"passivity_controlled_ticks\": " << s.passivity.controlledTicks << ",\n"
    << "  \"rate_limited_ticks\": " << s.passivity.rateLimitedTicks << ",\n"
    << "  \"max_force_step_n\": " << num(s.passivity.maxForceStep) << ",\n"
    << "  \"colgate_max_stiffness\": " << num(s.colgateMaxStiffness) << ",\n"
    << "  \"runaway\": " << (s.runaway.empty() ? std::string("null") : jsonString(s.runaway)) << ",\n"
    << "  \"final_position\": [" << num(s.finalPosition.x()) << ", " << num(s.finalPosition.y()) << ", "
    << num(s.finalPosition.z()) << "]\n"
    << "}\n";
  return o.str();
}

}  // namespace sdfccd::haptics
