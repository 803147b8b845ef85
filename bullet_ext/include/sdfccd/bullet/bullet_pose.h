/// @file
/// @brief Pose helpers at the Bullet border: btTransform / btVector3 to and from the core's double types, and
/// the body transform that puts a mesh where its file has it.
///
/// @details The core computes in double (Vec3, Rigid = Eigen::Isometry3d); Bullet in btScalar. A body built from a
/// mesh is simulated in its *body frame*: centre of mass at the origin, axes along the principal axes of inertia
/// (BodyModel). That frame differs from the mesh file's frame (for the Stanford bunny by 35.7 degrees and 3.5 cm),
/// so placing a btRigidBody at the pose you want the *mesh* to have rotates and shifts it. Use
/// bodyTransformForMeshPose():
/// @code
///   auto shape = std::make_unique<sdfccd::bullet::SdfccdShape>(model);
///   btTransform meshPose(btQuaternion::getIdentity(), btVector3(0, 1, 0));  // where the file's mesh should be
///   btDefaultMotionState motion(sdfccd::bullet::bodyTransformForMeshPose(*model, meshPose));
/// @endcode
/// and meshPoseOfBody() to read a body's pose back in the mesh file's frame (rendering, export).
///
/// Ownership: plain value functions; nothing is kept. Header-only.
#pragma once

#include <LinearMath/btQuaternion.h>
#include <LinearMath/btTransform.h>
#include <LinearMath/btVector3.h>

#include "sdfccd/math_types.h"
#include "sdfccd/model/body_model.h"

namespace sdfccd::bullet {

inline Vec3 toVec3(const btVector3& v) {
  return Vec3(double(v.x()), double(v.y()), double(v.z()));
}

inline btVector3 toBtVector3(const Vec3& v) {
  return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z()));
}

/// The rotation is re-orthonormalised through a normalised quaternion (btTransform holds btScalar).
inline Rigid toRigid(const btTransform& t) {
  Rigid r = Rigid::Identity();
  const btQuaternion q = t.getRotation();
  r.linear() = Quat(double(q.w()), double(q.x()), double(q.y()), double(q.z())).normalized().toRotationMatrix();
  r.translation() = toVec3(t.getOrigin());
  return r;
}

inline btTransform toBtTransform(const Rigid& r) {
  const Quat q(r.linear());
  return btTransform(btQuaternion(btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w())),
                     toBtVector3(Vec3(r.translation())));
}

/// The body transform (worldFromBody, what btRigidBody and btMotionState take) that puts the model's mesh at
/// `worldFromMesh`, the pose of the mesh file's own frame (after the model's scale).
inline btTransform bodyTransformForMeshPose(const BodyModel& model, const btTransform& worldFromMesh) {
  return toBtTransform(toRigid(worldFromMesh) * model.modelFromBody());
}

/// The pose of the mesh file's frame for a body at `worldFromBody` (the inverse of bodyTransformForMeshPose).
inline btTransform meshPoseOfBody(const BodyModel& model, const btTransform& worldFromBody) {
  return toBtTransform(toRigid(worldFromBody) * model.modelFromBody().inverse());
}

}  // namespace sdfccd::bullet
