/// @file
/// @brief PassivityController: observer, force-rate limit and energy-bounding controller (see passivity.h).
#include "sdfccd/haptics/passivity.h"

#include <algorithm>
#include <cmath>

#include "coupling/vector_limits.h"
#include "sdfccd/error.h"

namespace sdfccd::haptics {

namespace {

/// `next` moved towards from `last` by at most `maxStep` (0: unlimited); sets `limited` when it had to.
Vec3 limitStep(const Vec3& last, const Vec3& next, double maxStep, bool& limited) {
  if (!(maxStep > 0.0)) return next;
  const Vec3 d = next - last;
  const double n = d.norm();
  if (n <= maxStep) return next;
  limited = true;
  return last + d * (maxStep / n);
}

}  // namespace

PassivityController::PassivityController(const PassivitySettings& settings) : m_settings(settings) {
  const auto ok = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!ok(settings.maxForceStep) || !ok(settings.maxTorqueStep))
    throw Error("passivity: maxForceStep and maxTorqueStep must be finite and >= 0");
  if (!(settings.maxForce > 0.0) || !(settings.maxTorque > 0.0))
    throw Error("passivity: maxForce and maxTorque must be positive");
}

Vec6 PassivityController::filter(const DeviceState& state, const Vec6& wrench) {
  const Rigid& pose = state.body.worldFromBody;
  Vec6 predictedMove = Vec6::Zero();
  if (m_started) {
    // Observer: the work the last wrench did on the device over the last tick.
    const Vec6 move = poseDifference(m_lastPose, pose);
    m_stats.energy -= m_lastWrench.dot(move);
    m_stats.deficitBound += m_lastWrench.norm() * (move - m_lastMove).norm();
    m_stats.minEnergy = std::min(m_stats.minEnergy, m_stats.energy);
    m_lastMove = move;
    predictedMove = move;
  }
  Vec6 out = wrench.allFinite() ? wrench : Vec6::Zero();
  out.head<3>() = clampNorm(out.head<3>(), m_settings.maxForce);
  out.tail<3>() = clampNorm(out.tail<3>(), m_settings.maxTorque);
  bool limited = false;
  out.head<3>() = limitStep(m_lastWrench.head<3>(), out.head<3>(), m_settings.maxForceStep, limited);
  out.tail<3>() = limitStep(m_lastWrench.tail<3>(), out.tail<3>(), m_settings.maxTorqueStep, limited);
  m_stats.rateLimitedTicks += limited;
  if (m_settings.controller) {
    // Controller (energy bounding): the predicted work of this tick may not exceed the energy in store.
    const double predictedWork = out.dot(predictedMove);
    const double budget = std::max(m_stats.energy, 0.0);
    if (predictedWork > budget) {
      out *= budget / predictedWork;
      ++m_stats.controlledTicks;
    }
  }
  if (m_started) {
    m_stats.maxForceStep = std::max(m_stats.maxForceStep, (out.head<3>() - m_lastWrench.head<3>()).norm());
    m_stats.maxTorqueStep = std::max(m_stats.maxTorqueStep, (out.tail<3>() - m_lastWrench.tail<3>()).norm());
  }
  m_started = true;
  m_lastPose = pose;
  m_lastWrench = out;
  return out;
}

double colgateMaxStiffness(double physicalDamping, double period, double virtualDamping) {
  if (!(period > 0.0)) throw Error("colgateMaxStiffness: period must be positive");
  return std::max(0.0, 2.0 * (physicalDamping - std::abs(virtualDamping)) / period);
}

}  // namespace sdfccd::haptics
