/// @file
/// @brief DeviceEmulator: the emulated 6-DoF manipulandum and its fixed-rate loop.
#include "sdfccd/haptics/device_emulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "coupling/vector_limits.h"
#include "sdfccd/error.h"

namespace sdfccd::haptics {

DeviceEmulator::DeviceEmulator(const DeviceSettings& settings, UserScript script, const Rigid& worldFromDeviceStart)
    : m_settings(settings), m_script(std::move(script)) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  const auto nonNegative = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!positive(settings.rateHz) || settings.rateHz > 1e6) throw Error("device: rate must be in (0, 1e6] Hz");
  if (!positive(settings.mass) || !positive(settings.inertiaDiagonal.minCoeff()) ||
      !settings.inertiaDiagonal.allFinite())
    throw Error("device: mass and inertia must be positive and finite");
  if (!positive(settings.maxForce) || !positive(settings.maxTorque))
    throw Error("device: force and torque limits must be positive and finite");
  if (!nonNegative(settings.linearFriction) || !nonNegative(settings.angularFriction) ||
      !nonNegative(settings.userStiffness) || !nonNegative(settings.userDamping) ||
      !nonNegative(settings.userAngularStiffness) || !nonNegative(settings.userAngularDamping))
    throw Error("device: friction, stiffness and damping must be non-negative and finite");
  if (!worldFromDeviceStart.matrix().allFinite()) throw Error("device: start pose is not finite");
  m_state.body.worldFromBody = worldFromDeviceStart;
  m_state.worldFromTarget = m_script.targetAt(0.0);
}

DeviceEmulator::~DeviceEmulator() {
  stop();
}

void DeviceEmulator::step(const Vec6& renderedWrench) {
  const double dt = timestep();
  RigidBodyState& b = m_state.body;
  const Rigid target = m_script.targetAt(m_state.time);
  const Vec6 toTarget = poseDifference(b.worldFromBody, target);
  Vec6 user;
  user.head<3>() = m_settings.userStiffness * toTarget.head<3>() - m_settings.userDamping * b.linearVelocity;
  user.tail<3>() =
      m_settings.userAngularStiffness * toTarget.tail<3>() - m_settings.userAngularDamping * b.angularVelocity;
  Vec6 rendered = renderedWrench.allFinite() ? renderedWrench : Vec6::Zero();  // a bad wrench renders nothing
  rendered.head<3>() = clampNorm(rendered.head<3>(), m_settings.maxForce);
  rendered.tail<3>() = clampNorm(rendered.tail<3>(), m_settings.maxTorque);

  const Vec3 force = user.head<3>() + rendered.head<3>() - m_settings.linearFriction * b.linearVelocity;
  const Vec3 torque = user.tail<3>() + rendered.tail<3>() - m_settings.angularFriction * b.angularVelocity;
  const Mat3 inertia = worldInertia(b.worldFromBody, m_settings.inertiaDiagonal);
  // Symplectic Euler: velocities first, then the pose with the new velocities.
  b.linearVelocity += dt / m_settings.mass * force;
  b.angularVelocity += dt * inertia.ldlt().solve(torque - b.angularVelocity.cross(inertia * b.angularVelocity));
  Vec6 move;
  move << dt * b.linearVelocity, dt * b.angularVelocity;
  b.worldFromBody = displacePose(b.worldFromBody, move);

  m_state.userWrench = user;
  m_state.renderedWrench = rendered;
  m_state.worldFromTarget = target;
  ++m_state.tick;
  m_state.time = static_cast<double>(m_state.tick) * dt;
}

}  // namespace sdfccd::haptics
