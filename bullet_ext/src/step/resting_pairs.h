/// @file
/// @brief Which pairs run no CCD because nothing in them moves.
///
/// @details Bullet itself skips a pair when neither body is active (btCollisionDispatcher::needsCollision), which
/// covers two sleeping bodies and a sleeping body on a static one that Bullet keeps asleep (ISLAND_SLEEPING,
/// what addRigidBody gives static bodies). It does run pairs with a static body that was activated (activate(),
/// DISABLE_DEACTIVATION) and with a kinematic body, active by construction, even when it stands still. Such a
/// pair with a sleeping body changes nothing: a sleeping body is at rest with infinite mass for the step
/// (motion_prediction.h), so no impulse, no clamp; its CCD would only repeat last step's answer.
#pragma once

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

namespace sdfccd::bullet::detail {

/// The body does not move this step: static, not active (sleeping or disabled), or kinematic at zero velocity.
inline bool bodyAtRest(const btCollisionObject& object) {
  if (object.isStaticObject() || !object.isActive()) return true;
  if (!object.isKinematicObject()) return false;
  const btRigidBody* rigid = btRigidBody::upcast(&object);
  return rigid != nullptr && rigid->getLinearVelocity().isZero() && rigid->getAngularVelocity().isZero();
}

/// Neither body of the pair moves.
inline bool pairAtRest(const btCollisionObject& a, const btCollisionObject& b) {
  return bodyAtRest(a) && bodyAtRest(b);
}

}  // namespace sdfccd::bullet::detail
