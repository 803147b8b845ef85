/// @file
/// @brief SessionGuard: the runaway watchdog of a haptic session (see session_guard.h).
#include "session/session_guard.h"

#include <algorithm>
#include <limits>

namespace sdfccd::haptics {

namespace {

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
  // A moving obstacle pushes the object as the hand does: the faster of the two.
  double peak = scene.script.peakSpeed();
  for (const HapticObstacle& o : scene.obstacles)
    if (o.path.keys) peak = std::max(peak, o.path.keys->peakSpeed());
  hand.velocity = Vec3(peak, 0.0, 0.0);
  g.bodies = {object, hand};
  return g;
}

}  // namespace

SessionGuard::SessionGuard(const HapticScene& scene)
    : m_guard(guardScene(scene), 0.0),
      m_action(scene.guard.action),
      m_mass(scene.mass),
      m_inertiaDiagonal(scene.inertiaDiagonal),
      m_tick(1.0 / scene.device.rateHz),
      m_lastPose(scene.worldFromBodyStart) {}

bool SessionGuard::observePose(double time, const Rigid& pose) {
  Vec6 velocity = Vec6::Zero();
  if (!pose.isApprox(m_lastPose, 0.0)) {
    velocity = poseDifference(m_lastPose, pose) / std::max(m_tick, time - m_lastChange);
    m_lastPose = pose;
    m_lastChange = time;
  }
  return check(time, pose, velocity.head<3>(), velocity.tail<3>());
}

bool SessionGuard::check(double time, const Rigid& pose, const Vec3& velocity, const Vec3& angularVelocity) {
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

}  // namespace sdfccd::haptics
