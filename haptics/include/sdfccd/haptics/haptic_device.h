/// @file
/// @brief HapticDevice: the port a haptic loop talks to (read the pose and twist, write the wrench, one tick per
/// period), and DeviceLoop: the fixed-rate loop that drives any such device, in real time or in virtual time.
///
/// @details A device is anything that has a pose and a twist at the start of each tick and renders a wrench during
/// it: the emulated manipulandum (device_emulator.h), a recorded trajectory (trajectory_player.h), or a lab's
/// driver wrapped in this interface. One tick of the loop:
///   1. the tick handler sees state() (pose, twist, tick number, time) and returns the wrench to render;
///   2. write(wrench) hands it to the device, which renders it for one period and advances to the next tick.
/// The tick's deadline is start + n * period() (no drift).
///
/// DeviceLoop runs the ticks:
/// - runVirtual(): back to back on the calling thread, no sleeping: deterministic, for tests.
/// - start(): real time on its own thread; each tick waits with sleep_until on the steady clock for its deadline. It
///   records the wake-up lateness (jitter) and counts overruns (a tick that ends after the next deadline; the
///   schedule then skips the missed deadlines instead of bursting to catch up). Real-time priority (SCHED_FIFO via
///   pthread_setschedparam) is an opt-in of DeviceLoopOptions; whether the system granted it is in the stats.
/// A handler that throws does not terminate the process: the loop keeps the exception's message (error()), writes a
/// zero wrench for that tick and stops after it (the device is left rendering nothing).
///
/// Thread safety: while a real-time loop runs, only its thread touches the device; other threads exchange data with
/// the handler (LatestValue, latest_value.h). stats() and error() may be read after wait() / stop() or runVirtual.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "sdfccd/haptics/rigid_body_state.h"
#include "sdfccd/haptics/spatial_types.h"

namespace sdfccd::haptics {

/// What the device is doing at one tick.
struct DeviceState {
  std::int64_t tick = 0;                      ///< ticks done
  double time = 0.0;                          ///< s, tick * period
  RigidBodyState body;                        ///< the manipulandum (x_h) and its twist
  Rigid worldFromTarget = Rigid::Identity();  ///< emulator: the user's target at this time (else the pose)
  Vec6 userWrench = Vec6::Zero();             ///< emulator: N, N m the hand applied last step (else 0)
  Vec6 renderedWrench = Vec6::Zero();         ///< N, N m: what the device rendered last step (after its clamping)
};

/// The haptic device port.
class HapticDevice {
 public:
  virtual ~HapticDevice() = default;
  /// Hz, the tick rate; period() = 1 / rateHz() is the tick's length and the spacing of its deadlines.
  virtual double rateHz() const = 0;
  double period() const { return 1.0 / rateHz(); }
  /// The state at the start of the current tick.
  virtual const DeviceState& state() const = 0;
  /// Renders `wrench` (N, N m, world axes, on the device) during the current tick and advances to the next. A
  /// non-finite wrench renders nothing.
  virtual void write(const Vec6& wrench) = 0;
  /// Ticks the device can still run; negative: no end of its own (the player ends with its recording).
  virtual std::int64_t ticksLeft() const { return -1; }
};

/// Timing of a run of the loop.
struct LoopTimingStats {
  std::int64_t ticks = 0;
  double elapsedSeconds = 0.0;  ///< s, wall clock (virtual time: ticks * period)
  double achievedRateHz = 0.0;  ///< ticks / elapsed
  double jitterP50Us = 0.0;     ///< us, median wake-up lateness
  double jitterP99Us = 0.0;     ///< us
  double jitterMaxUs = 0.0;     ///< us
  double handlerP99Us = 0.0;    ///< us, 99th percentile of the tick handler + write time
  std::int64_t overruns = 0;    ///< ticks that ended after the next deadline
  bool virtualTime = false;
  /// Real-time priority: "off" (not asked), "granted (SCHED_FIFO N)", or "denied (SCHED_FIFO N): reason".
  std::string realTimePriority = "off";
};

/// The haptic loop body: gets the device state before the tick, returns the wrench to render during it.
using TickHandler = std::function<Vec6(const DeviceState& state)>;

/// How a real-time loop runs.
struct DeviceLoopOptions {
  bool realTimePriority = false;  ///< ask for SCHED_FIFO at `priority` (needs CAP_SYS_NICE or an rtprio limit)
  int priority = 80;              ///< 1..99
};

/// The fixed-rate loop of one device (see the file comment).
class DeviceLoop {
 public:
  explicit DeviceLoop(HapticDevice& device) : m_device(device) {}
  ~DeviceLoop();
  DeviceLoop(const DeviceLoop&) = delete;
  DeviceLoop& operator=(const DeviceLoop&) = delete;

  /// Runs up to `ticks` ticks on this thread without sleeping (fewer if the handler calls requestStop(), the device
  /// runs out, or the handler throws).
  LoopTimingStats runVirtual(std::int64_t ticks, const TickHandler& handler);
  /// Starts the real-time loop on its own thread; it stops by itself after `maxTicks` ticks (or at stop()). Throws
  /// sdfccd::Error if already running or on a priority outside 1..99.
  void start(TickHandler handler, std::int64_t maxTicks, const DeviceLoopOptions& options = {});
  /// Asks the loop to stop and joins it. Safe to call twice.
  void stop();
  /// Asks the loop to stop after the current tick without joining: callable from the tick handler itself.
  void requestStop() { m_stopRequested.store(true, std::memory_order_relaxed); }
  bool stopRequested() const { return m_stopRequested.load(std::memory_order_relaxed); }
  /// True while the loop thread has ticks left to run.
  bool running() const { return m_running.load(std::memory_order_acquire); }
  /// Blocks until the loop has run its ticks (or was stopped), then joins it.
  void wait();

  const LoopTimingStats& stats() const { return m_stats; }
  /// The message of the exception that ended the loop ("" if none).
  const std::string& error() const { return m_error; }

 private:
  void loop(std::int64_t maxTicks, DeviceLoopOptions options);
  /// One tick: the handler's wrench written to the device; on an exception the message is kept, zero is written
  /// and the loop is asked to stop.
  void tick(const TickHandler& handler);

  HapticDevice& m_device;
  LoopTimingStats m_stats;
  std::string m_error;
  TickHandler m_handler;
  std::thread m_thread;
  std::atomic<bool> m_running{false};
  std::atomic<bool> m_stopRequested{false};
};

/// Percentile (0..100) of a sample set by nearest rank (copies; empty set: 0).
double percentile(std::vector<double> samples, double percent);

}  // namespace sdfccd::haptics
