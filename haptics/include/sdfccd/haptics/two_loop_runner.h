/// @file
/// @brief TwoLoopRunner: the paper's two asynchronous loops (Section 4.2) on any HapticDevice: a fixed-rate haptic
/// loop and a simulation loop that runs as fast as it can, exchanging only the newest values.
///
/// @details The runner owns the threads and the exchange of the device state; the caller gives the two bodies:
/// - simulate(deviceState): one simulation cycle against the newest device state the haptic loop published (the
///   caller publishes its own result, e.g. through a LatestValue, for the haptic tick to read). It returns false
///   when the cycle changed nothing (settled); the loop then yields its core until the device moves. May be empty:
///   a single loop (the penalty renderer runs its step inside the haptic tick, as the paper's admittance loop).
/// - haptic(deviceState): the haptic tick, returning the wrench to render.
/// Real time: the device loop runs on its own thread (DeviceLoop, haptic_device.h; SCHED_FIFO as an opt-in), the
/// simulation on another. Virtual time: each tick runs `simCyclesPerTick` simulation cycles, then the haptic tick,
/// on the calling thread, deterministically.
///
/// Failure: an exception in either body ends the session cleanly instead of terminating the process: the first
/// message is kept ("simulation loop: ..." or "haptic loop: ..."), the device gets a zero wrench on the tick that
/// sees the failure and no tick after it, and both threads are joined before run() returns. requestStop() (from a
/// body, e.g. a runaway guard) ends the loop after the current tick.
///
/// Thread safety: the bodies run on different threads in real time; they must share only thread-safe exchanges.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "sdfccd/haptics/haptic_device.h"

namespace sdfccd::haptics {

/// One simulation cycle against the newest device state; false: nothing changed (the loop may idle).
using SimulationCycle = std::function<bool(const DeviceState& device)>;

struct TwoLoopSettings {
  std::int64_t ticks = 0;    ///< haptic ticks to run (fewer if the device runs out or the loop is stopped)
  bool realTime = false;     ///< true: two threads at the device's rate; false: virtual time
  int simCyclesPerTick = 1;  ///< virtual time: simulation cycles before each haptic tick
  DeviceLoopOptions loop;    ///< real time: the device loop's priority (opt-in)
};

struct TwoLoopResult {
  LoopTimingStats timing;
  std::string error;                  ///< the exception that ended the session ("" if none)
  std::int64_t simulationCycles = 0;  ///< cycles the simulation loop ran
};

class TwoLoopRunner {
 public:
  /// Throws sdfccd::Error on ticks < 0 or simCyclesPerTick outside 1..1000.
  TwoLoopRunner(HapticDevice& device, const TwoLoopSettings& settings);
  /// Runs the loops to the end (see the file comment). `haptic` must be set.
  TwoLoopResult run(const SimulationCycle& simulate, const TickHandler& haptic);
  /// Ends the loops after the current haptic tick; callable from either body.
  void requestStop() { m_stop.store(true, std::memory_order_relaxed); }

 private:
  TwoLoopResult runVirtual(const SimulationCycle& simulate, const TickHandler& haptic);
  TwoLoopResult runRealTime(const SimulationCycle& simulate, const TickHandler& haptic);

  HapticDevice& m_device;
  TwoLoopSettings m_settings;
  std::atomic<bool> m_stop{false};
};

}  // namespace sdfccd::haptics
