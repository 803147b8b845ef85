/// @file
/// @brief PassivityController: a passivity observer and controller on the device port (after Hannaford & Ryu,
/// "Time-domain passivity control of haptic interfaces", 2002), a force-rate limit, and Colgate's stiffness bound.
///
/// @details The port: at tick n the device is at pose x_n; the renderer's wrench F_n is held during the tick, while
/// the device moves by dx_n = x_{n+1} - x_n (6-D: translation, rotation vector; a constant wrench over such a move
/// does exactly the work F_n . dx_n on the device). The virtual environment (renderer + coupling) is passive when
/// the energy it has absorbed,
///     E_n = - sum_{k < n} F_k . dx_k            (J; the observer, from the device's poses only),
/// never goes negative: it can give back what the user put in, never more.
/// The controller, every tick, in this order:
///   1. clamps F_n to the device's force and torque limits (so the device's own clamp never changes the work);
///   2. limits the change of the force and of the torque per tick (maxForceStep, maxTorqueStep: force continuity;
///      the constraint force otherwise jumps by up to 3.2 N in one 1 ms tick);
///   3. predicts the tick's move by the last one, dx^_n = dx_{n-1}, and when the predicted work F_n . dx^_n would
///      exceed the energy in store, max(E_n, 0), scales the wrench down by s = max(E_n, 0) / (F_n . dx^_n) < 1
///      (energy bounding: the wrench only shrinks, so the limits of steps 1 and 2 still hold; passivity has the
///      last word, so on such a tick the force may drop faster than the rate limit).
/// The stated bound (what the tests check): the environment gains energy only through the prediction error of
/// step 3, at most |F_n| |dx_n - dx_{n-1}| per tick (|F| the 6-D norm; dx_n - dx_{n-1} is the device's
/// acceleration times T^2), so
///     E_n >= - sum_{k < n} |F_k| |dx_k - dx_{k-1}|     for every n,
/// and any deficit is paid back by the next ticks in which the device moves against the wrench (while E < 0, a
/// wrench that would do positive work is cut to zero). The sum is kept in stats().deficitBound.
///
/// Colgate's bound (Colgate & Schenkel 1997): a virtual wall of stiffness K and damping B sampled with period T on
/// a device with physical damping b is passive iff b > K T / 2 + |B|. colgateMaxStiffness() gives K = 2 (b - |B|) /
/// T; the emulated device's b is its friction plus the hand's damping (1 + 8 N s/m at 1 kHz: 1.8e4 N/m). Above it
/// a wall chatters without the controller; with it, it does not gain energy.
#pragma once

#include <cstdint>
#include <limits>

#include "sdfccd/haptics/haptic_device.h"
#include "sdfccd/haptics/spatial_types.h"

namespace sdfccd::haptics {

struct PassivitySettings {
  bool controller = true;      ///< the controller of step 3 (the observer always runs: stats())
  double maxForceStep = 0.0;   ///< N per tick; 0: no force-rate limit
  double maxTorqueStep = 0.0;  ///< N m per tick; 0: no torque-rate limit
  double maxForce = std::numeric_limits<double>::infinity();   ///< N, the device's limit (step 1)
  double maxTorque = std::numeric_limits<double>::infinity();  ///< N m
};

/// What the controller saw over a run.
struct PassivityStats {
  double energy = 0.0;                ///< J, E_n at the last tick observed (energy absorbed by the environment)
  double minEnergy = 0.0;             ///< J, the lowest E_n
  double deficitBound = 0.0;          ///< J, sum |F_k| |dx_k - dx_{k-1}|: -E_n never exceeds it
  std::int64_t controlledTicks = 0;   ///< ticks whose wrench step 3 scaled down
  std::int64_t rateLimitedTicks = 0;  ///< ticks whose force or torque change step 2 limited
  double maxForceStep = 0.0;          ///< N, the largest change of the output force between two ticks
  double maxTorqueStep = 0.0;         ///< N m
};

class PassivityController {
 public:
  /// Throws sdfccd::Error on negative or non-finite steps, or non-positive limits.
  explicit PassivityController(const PassivitySettings& settings);
  /// The wrench to write at the tick `state` describes (call once per tick, in order, with the renderer's wrench).
  Vec6 filter(const DeviceState& state, const Vec6& wrench);
  const PassivityStats& stats() const { return m_stats; }
  const PassivitySettings& settings() const { return m_settings; }

 private:
  PassivitySettings m_settings;
  PassivityStats m_stats;
  bool m_started = false;
  Rigid m_lastPose = Rigid::Identity();
  Vec6 m_lastWrench = Vec6::Zero();
  Vec6 m_lastMove = Vec6::Zero();
  Vec6 m_lastPrediction = Vec6::Zero();
};

/// Colgate's largest passive wall stiffness, 2 (b - |B|) / T (N/m; 0 when |B| >= b): b the device's physical
/// damping (N s/m), B the wall's virtual damping, T the sampling period (s).
double colgateMaxStiffness(double physicalDamping, double period, double virtualDamping = 0.0);

}  // namespace sdfccd::haptics
