/// @file
/// @brief Motion prediction per body and child frame per wrapper (see motion_prediction.h).
#include "step/motion_prediction.h"

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <LinearMath/btTransformUtil.h>

#include "common/bullet_conversions.h"

namespace sdfccd::bullet::detail {

PredictedMotion predictBodyMotion(const btCollisionObject& object, double timeStep) {
  PredictedMotion m;
  const btTransform start = object.getWorldTransform();
  btTransform end = start;
  const btRigidBody* rigid = btRigidBody::upcast(&object);
  if (rigid != nullptr && !rigid->isStaticOrKinematicObject()) {
    if (!rigid->isActive()) {
      m.asleep = true;  // at rest, infinite mass for this step
    } else {
      m.dynamicBody = const_cast<btRigidBody*>(rigid);  // impulses are applied later
      // The symplectic Euler step Bullet's integrateVelocities + integrateTransforms will take (no contact
      // constraints come from us): v' = v + F/m dt, w' = w + I^-1 tau dt, then the pose from (v', w').
      const btVector3 v0 = rigid->getLinearVelocity();
      const btVector3 w0 = rigid->getAngularVelocity();
      const btVector3 v1 = v0 + rigid->getTotalForce() * (rigid->getInvMass() * btScalar(timeStep));
      const btVector3 w1 = w0 + rigid->getInvInertiaTensorWorld() * rigid->getTotalTorque() * btScalar(timeStep);
      btTransformUtil::integrateTransform(start, v1, w1, btScalar(timeStep), end);
      m.velocity.linearStart = toVec3(v0);
      m.velocity.linearEnd = toVec3(v1);
      m.velocity.angularStart = toVec3(w0);
      m.velocity.angularEnd = toVec3(w1);
      m.mass.inverseMass = double(rigid->getInvMass());
      m.mass.inverseInertiaInWorld = toMat3(rigid->getInvInertiaTensorWorld());
    }
  } else if (rigid != nullptr && rigid->isKinematicObject()) {
    m.kinematic = true;
    const btVector3 v = rigid->getLinearVelocity();
    const btVector3 w = rigid->getAngularVelocity();
    btTransformUtil::integrateTransform(start, v, w, btScalar(timeStep), end);
    m.velocity.linearStart = m.velocity.linearEnd = toVec3(v);
    m.velocity.angularStart = m.velocity.angularEnd = toVec3(w);
  }
  m.worldFromBodyStart = toRigid(start);
  m.worldFromBodyEnd = toRigid(end);
  return m;
}

Rigid bodyFromChild(const btCollisionObjectWrapper& wrap) {
  const btTransform& body = wrap.getCollisionObject()->getWorldTransform();
  const btTransform& child = wrap.getWorldTransform();
  if (&body == &child) return Rigid::Identity();  // a plain body: the wrapper shows the object's own transform
  return Rigid(toRigid(body).inverse() * toRigid(child));
}

}  // namespace sdfccd::bullet::detail
