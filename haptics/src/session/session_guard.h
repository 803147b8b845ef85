/// @file
/// @brief SessionGuard: the runaway watchdog of a haptic session, internal to the session.
#pragma once

#include <optional>
#include <string>

#include "sdfccd/haptics/haptic_scene.h"
#include "sdfccd/haptics/rigid_body_state.h"
#include "sdfccd/model/runaway_guard.h"

namespace sdfccd::haptics {

/// Checks the simulated object's state on every haptic tick. On a violation with action "stop" the tick renders
/// zero force and the loop stops; with "report" the first violation is kept and the session goes on. The scene as
/// the guard (sdfccd/model/runaway_guard.h) sees it: the simulated object, dynamic and at rest at its start pose,
/// and the user's hand as a kinematic body moving at the script's peak speed, so the guard grants the object what
/// a moving wall may give a body (twice the wall's speed). Used by the haptic loop's thread only.
class SessionGuard {
 public:
  explicit SessionGuard(const HapticScene& scene);

  /// A body with velocities (the penalty renderer's object). True: stop the loop now.
  bool observeState(double time, const RigidBodyState& state) {
    return check(time, state.worldFromBody, state.linearVelocity, state.angularVelocity);
  }
  /// A quasi-static pose (the god-object): its velocity is the displacement since the pose last changed over the
  /// time since then (at least one tick), so a simulation loop that lags and then catches up is not a runaway.
  bool observePose(double time, const Rigid& pose);

  bool stopped() const { return m_stopped; }
  const std::string& violation() const { return m_violation; }  ///< the first one; "" if none

 private:
  bool check(double time, const Rigid& pose, const Vec3& velocity, const Vec3& angularVelocity);

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

}  // namespace sdfccd::haptics
