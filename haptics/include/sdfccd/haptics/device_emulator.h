/// @file
/// @brief DeviceEmulator: a 6-DoF haptic manipulandum run by a fixed-rate 1 kHz loop (paper Section 4).
///
/// @details The emulated device is a rigid body (mass, inertia, viscous friction) pulled by a scripted user
/// through a spring-damper towards the script's target pose, and pushed by the wrench the haptic renderer
/// sends (clamped to the device's force and torque limits, as a real device saturates). Each tick:
///   1. the tick handler (the haptic loop body: virtual coupling, penalty step, or reading -F_c from the
///      simulation loop) sees the device state and returns the wrench to render;
///   2. the device integrates one symplectic Euler step of dt = 1 / rate under user + rendered wrench.
/// This is the paper's admittance mode: the device's pose follows from forces.
///
/// Two ways to run the same ticks:
/// - start(): real time on its own std::thread; each tick waits with sleep_until on the steady clock for its
///   deadline (deadline n = start + n / rate, no drift). It records the wake-up lateness (jitter) and counts
///   overruns (a tick that ends after the next deadline; the schedule then skips the missed deadlines
///   instead of bursting to catch up).
/// - runVirtual(): the same ticks back to back on the calling thread, no sleeping: deterministic, for tests.
///
/// Thread safety: while the loop runs (between start() and stop()), only the loop thread touches the device
/// state; other threads exchange data with the tick handler through LatestValue (latest_value.h).
/// state() and stats() may be read after stop() (or after runVirtual returns).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <thread>
#include <vector>

#include "sdfccd/haptics/rigid_body_state.h"
#include "sdfccd/haptics/spatial_types.h"
#include "sdfccd/haptics/user_script.h"

namespace sdfccd::haptics {

/// The emulated device and the emulated hand.
struct DeviceSettings {
  double rateHz = 1000.0;                       ///< Hz, haptic loop rate
  double mass = 0.3;                            ///< kg, apparent mass of the manipulandum
  Vec3 inertiaDiagonal = Vec3::Constant(4e-4);  ///< kg m^2, body axes
  double linearFriction = 1.0;                  ///< N s/m, viscous friction of the mechanism
  double angularFriction = 0.005;               ///< N m s/rad
  double maxForce = 30.0;                       ///< N, largest force the device renders (per vector norm)
  double maxTorque = 3.0;                       ///< N m, largest torque the device renders
  double userStiffness = 200.0;                 ///< N/m, the hand's grip spring towards the target
  double userDamping = 8.0;                     ///< N s/m
  double userAngularStiffness = 2.0;            ///< N m/rad
  double userAngularDamping = 0.05;             ///< N m s/rad
};

/// What the device is doing at one tick.
struct DeviceState {
  std::int64_t tick = 0;                      ///< ticks done
  double time = 0.0;                          ///< s, tick / rate
  RigidBodyState body;                        ///< the manipulandum (x_h)
  Rigid worldFromTarget = Rigid::Identity();  ///< the user's target at this time
  Vec6 userWrench = Vec6::Zero();             ///< N, N m: what the hand applied last step
  Vec6 renderedWrench = Vec6::Zero();         ///< N, N m: what the device rendered last step (after clamping)
};

/// Timing of a run of the loop.
struct LoopTimingStats {
  std::int64_t ticks = 0;
  double elapsedSeconds = 0.0;  ///< s, wall clock (virtual time: ticks / rate)
  double achievedRateHz = 0.0;  ///< ticks / elapsed
  double jitterP50Us = 0.0;     ///< us, median wake-up lateness
  double jitterP99Us = 0.0;     ///< us
  double jitterMaxUs = 0.0;     ///< us
  double handlerP99Us = 0.0;    ///< us, 99th percentile of the tick handler + step time
  std::int64_t overruns = 0;    ///< ticks that ended after the next deadline
  bool virtualTime = false;
};

/// The haptic loop body: gets the device state before the step, returns the wrench to render during it.
using TickHandler = std::function<Vec6(const DeviceState& state)>;

class DeviceEmulator {
 public:
  /// Throws sdfccd::Error on non-positive or non-finite settings.
  DeviceEmulator(const DeviceSettings& settings, UserScript script, const Rigid& worldFromDeviceStart);
  ~DeviceEmulator();
  DeviceEmulator(const DeviceEmulator&) = delete;
  DeviceEmulator& operator=(const DeviceEmulator&) = delete;

  /// One tick without a handler: applies `renderedWrench` (clamped) and the user's pull for dt.
  void step(const Vec6& renderedWrench);

  /// Runs `ticks` ticks on this thread without sleeping (deterministic virtual time), fewer if the handler calls
  /// requestStop().
  LoopTimingStats runVirtual(std::int64_t ticks, const TickHandler& handler);

  /// Starts the real-time loop on its own thread; it stops by itself after `maxTicks` ticks (or at stop()).
  /// Throws sdfccd::Error if already running.
  void start(TickHandler handler, std::int64_t maxTicks);
  /// Asks the loop to stop and joins it. Safe to call twice.
  void stop();
  /// Asks the loop to stop after the current tick without joining: callable from the tick handler itself (the
  /// runaway guard ends a session this way), in real time and in runVirtual alike.
  void requestStop() { m_stopRequested.store(true, std::memory_order_relaxed); }
  /// True while the loop thread has ticks left to run.
  bool running() const { return m_running.load(std::memory_order_acquire); }
  /// Blocks until the loop has run its ticks (or was stopped), then joins it.
  void wait();

  const DeviceState& state() const { return m_state; }
  const LoopTimingStats& stats() const { return m_stats; }
  const DeviceSettings& settings() const { return m_settings; }
  double timestep() const { return 1.0 / m_settings.rateHz; }  ///< s

 private:
  void loop(std::int64_t maxTicks);

  DeviceSettings m_settings;
  UserScript m_script;
  DeviceState m_state;
  LoopTimingStats m_stats;
  TickHandler m_handler;
  std::thread m_thread;
  std::atomic<bool> m_running{false};
  std::atomic<bool> m_stopRequested{false};
};

/// Percentile (0..100) of a sample set by nearest rank (copies; empty set: 0).
double percentile(std::vector<double> samples, double percent);

}  // namespace sdfccd::haptics
