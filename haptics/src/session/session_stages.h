/// @file
/// @brief The stages of a haptic session's two loops (internal to the haptics library; see haptic_session.h).
///
/// @details The haptic tick and the simulation cycle, stage by stage:
/// - constraint methods (constraint_loops.cpp): the simulation cycle is
///     injectFault -> stepGodObject (timed: the obstacles to the tick's time, QP, CCD) -> measure (penetration, log)
///     -> publish (for the haptic loop);
///   the haptic tick is newestSimulation -> guard (SessionGuard::observePose) -> DevicePort::render.
/// - penalty methods (penalty_loop.cpp): one haptic tick runs the simulation too:
///     injectFault -> stepRenderer (timed) -> measure -> guard (SessionGuard::observeState) -> DevicePort::render.
/// DevicePort::render (device_port.cpp) is the end of every tick: the passivity controller (or zero once the guard
/// stopped the session), then the tick's record.
#pragma once

#include <chrono>
#include <cstdint>
#include <vector>

#include "sdfccd/haptics/god_object.h"
#include "sdfccd/haptics/haptic_scene.h"
#include "sdfccd/haptics/haptic_session.h"
#include "sdfccd/haptics/latest_value.h"
#include "sdfccd/haptics/passivity.h"
#include "sdfccd/haptics/penalty_renderer.h"
#include "sdfccd/haptics/two_loop_runner.h"
#include "sdfccd/thread_cpu_time.h"
#include "session/fault_injection.h"
#include "session/session_guard.h"

namespace sdfccd::haptics {

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

  /// Runs one simulation step, `step()`, and logs its thread CPU time and wall time (ms); returns its result.
  template <class Step>
  auto timed(const Step& step) {
    using Clock = std::chrono::steady_clock;
    const double cpu0 = threadCpuSeconds();
    const auto t0 = Clock::now();
    auto r = step();
    const auto t1 = Clock::now();
    cycleCpuMs.push_back(1e3 * (threadCpuSeconds() - cpu0));
    cycleMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    return r;
  }
  /// What the step just timed hands the haptic loop, observed by the log: the wrench, the pose reached, its contacts
  /// and the penetration measured there.
  SimulationOutput measure(const HapticScene& scene, const Vec6& wrenchOnDevice, const Rigid& worldFromSimulation,
                           int contacts, double penetration);
};

/// The end of every haptic tick: the wrench through the device port's passivity controller (passivity.h), or zero
/// once the runaway guard has stopped the session (and the loops are asked to stop after this tick); then the tick's
/// record. Used by the haptic loop's thread only.
class DevicePort {
 public:
  DevicePort(const HapticScene& scene, const HapticSessionSettings& settings, std::vector<HapticTickRecord>& ticks);

  /// The loops to stop when the guard stops the session.
  void attach(TwoLoopRunner& runner) { m_runner = &runner; }
  SessionGuard& guard() { return m_guard; }
  const SessionGuard& guard() const { return m_guard; }
  const PassivityController& passivity() const { return m_passivity; }

  /// The wrench to render this tick for the newest simulation output `sim`; `stop`: the guard stopped the session.
  Vec6 render(const DeviceState& state, SimulationOutput sim, bool stop);

 private:
  void record(const DeviceState& state, const SimulationOutput& sim);

  SessionGuard m_guard;
  PassivityController m_passivity;
  bool m_recordTicks;
  std::vector<HapticTickRecord>& m_ticks;
  TwoLoopRunner* m_runner = nullptr;
};

/// The constraint methods' two loops (constraint_loops.cpp): the god-object's simulation cycle on its own loop,
/// exchanging only the newest values with the haptic tick.
class ConstraintLoops {
 public:
  ConstraintLoops(const HapticScene& scene, const SessionFaults& faults, GodObject& god, SimulationLog& log,
                  DevicePort& port);

  /// One simulation cycle against the newest device state; false: it moved nothing (the loop may idle).
  bool simulationCycle(const DeviceState& device);
  /// One haptic tick: the newest simulation output, guarded and rendered.
  Vec6 hapticTick(const DeviceState& state);

 private:
  void injectFault() const;
  GodObjectStepResult stepGodObject(const DeviceState& device);
  SimulationOutput measure(const GodObjectStepResult& r);
  void publish(const SimulationOutput& out) { m_simulation.publish(out); }
  SimulationOutput newestSimulation();

  const HapticScene& m_scene;
  const SessionFaults& m_faults;
  GodObject& m_god;
  SimulationLog& m_log;  // the simulation loop's
  DevicePort& m_port;    // the haptic loop's
  bool m_movingObstacles;
  LatestValue<SimulationOutput> m_simulation;
};

/// The penalty methods' one loop (penalty_loop.cpp): the implicit penalty step runs inside the haptic tick (one
/// simulation step per tick, as the paper's admittance-mode loop).
class PenaltyLoop {
 public:
  PenaltyLoop(const HapticScene& scene, const SessionFaults& faults, PenaltyRenderer& renderer, SimulationLog& log,
              DevicePort& port);

  /// One haptic tick: the penalty step against the device state, guarded and rendered.
  Vec6 hapticTick(const DeviceState& state);

 private:
  void injectFault(const DeviceState& state) const;
  PenaltyStepResult stepRenderer(const DeviceState& state);
  SimulationOutput measure(const PenaltyStepResult& r);

  const HapticScene& m_scene;
  const SessionFaults& m_faults;
  PenaltyRenderer& m_renderer;
  SimulationLog& m_log;
  DevicePort& m_port;
};

}  // namespace sdfccd::haptics
