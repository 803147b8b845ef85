/// @file
/// @brief Motion prediction (design note 1.6, 1.7, 2.5, 2.8, 2.9): each collision object's rigid-body
/// motion over the step, and each wrapper's child frame in its body. Private to sdfccd::bullet.
///
/// @details The body motion is keyed by collision object (one per body and step), in the rigid body's
/// centre-of-mass frame (Bullet's world transform of a btRigidBody). A compound's children reach the narrowphase
/// as wrappers of the same object with worldFromChild = worldFromBody * childTransform: bodyFromChild() gives
/// that child's own frame, so each child gets its own pose, handles from the body's centre of mass and impulses
/// about it.
/// - dynamic and awake: the symplectic Euler step Bullet will take (gravity and applied forces included);
/// - kinematic: infinite mass, moving with its velocity (saveKinematicState's), swept [now, now + v dt];
/// - static, or dynamic but asleep (Bullet's rules): infinite mass, at rest for the step (no impulse, no wake-up:
///   Bullet's island manager wakes it when its island has an active member).
#pragma once

#include "sdfccd/math_types.h"
#include "sdfccd/response/penalty_model.h"

class btCollisionObject;
class btCollisionObjectWrapper;
class btRigidBody;

namespace sdfccd::bullet::detail {

/// One collision object's motion over the step.
struct PredictedMotion {
  btRigidBody* dynamicBody = nullptr;            ///< dynamic and awake: receives impulses; else null
  bool kinematic = false;                        ///< a kinematic rigid body (infinite mass, moving)
  bool asleep = false;                           ///< a dynamic body that is not active this step
  Rigid worldFromBodyStart = Rigid::Identity();  ///< centre-of-mass frame
  Rigid worldFromBodyEnd = Rigid::Identity();
  BodyVelocities velocity;  ///< of the centre of mass
  BodyInverseMass mass;     ///< zero unless dynamicBody
};

/// The motion of `object` over a step of `timeStep` seconds (see the file comment).
PredictedMotion predictBodyMotion(const btCollisionObject& object, double timeStep);

/// The wrapper's frame in its collision object's frame: identity for a plain body, the child transform for a
/// compound's child.
Rigid bodyFromChild(const btCollisionObjectWrapper& wrap);

}  // namespace sdfccd::bullet::detail
