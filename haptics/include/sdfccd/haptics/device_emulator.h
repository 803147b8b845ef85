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
/// It is a HapticDevice (haptic_device.h): write() is step(). Its own start() / runVirtual() run it with a DeviceLoop
/// (real time on its own thread with deadlines, or back to back in virtual time); any other runner (TwoLoopRunner,
/// runHapticSession with a device) drives it the same way.
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

#include "sdfccd/haptics/haptic_device.h"
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

class DeviceEmulator : public HapticDevice {
 public:
  /// Throws sdfccd::Error on non-positive or non-finite settings.
  DeviceEmulator(const DeviceSettings& settings, UserScript script, const Rigid& worldFromDeviceStart);
  ~DeviceEmulator();
  DeviceEmulator(const DeviceEmulator&) = delete;
  DeviceEmulator& operator=(const DeviceEmulator&) = delete;

  /// One tick without a handler: applies `renderedWrench` (clamped) and the user's pull for dt.
  void step(const Vec6& renderedWrench);

  // HapticDevice: write() is step().
  double rateHz() const override { return m_settings.rateHz; }
  const DeviceState& state() const override { return m_state; }
  void write(const Vec6& wrench) override { step(wrench); }

  /// The loop of this device (haptic_device.h), kept for the callers that run the emulator on its own.
  LoopTimingStats runVirtual(std::int64_t ticks, const TickHandler& handler) {
    return m_loop.runVirtual(ticks, handler);
  }
  void start(TickHandler handler, std::int64_t maxTicks, const DeviceLoopOptions& options = {}) {
    m_loop.start(std::move(handler), maxTicks, options);
  }
  void stop() { m_loop.stop(); }
  void requestStop() { m_loop.requestStop(); }
  bool running() const { return m_loop.running(); }
  void wait() { m_loop.wait(); }
  const LoopTimingStats& stats() const { return m_loop.stats(); }
  const DeviceSettings& settings() const { return m_settings; }
  double timestep() const { return 1.0 / m_settings.rateHz; }  ///< s

 private:
  DeviceSettings m_settings;
  UserScript m_script;
  DeviceState m_state;
  DeviceLoop m_loop{*this};
};

}  // namespace sdfccd::haptics
