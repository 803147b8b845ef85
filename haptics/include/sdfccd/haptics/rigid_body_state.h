/// @file
/// @brief The state of a rigid body in haptics (pose + twist) and the pose arithmetic the loops share:
/// 6-D pose differences, symplectic pose updates, pose interpolation (lerp + slerp).
///
/// @details Velocities are in world axes: `linearVelocity` of the body origin (its centre of mass), and
/// `angularVelocity`. A 6-D pose difference is (translation, rotation vector) in world axes; for a small
/// rotation it is the x_h - x_s of the paper's eq. (6).
#pragma once

#include <cmath>

#include "sdfccd/haptics/spatial_types.h"
#include "sdfccd/math_types.h"

namespace sdfccd::haptics {

/// Pose and velocity of a rigid body whose frame origin is its centre of mass.
struct RigidBodyState {
  Rigid worldFromBody = Rigid::Identity();
  Vec3 linearVelocity = Vec3::Zero();   ///< m/s, world
  Vec3 angularVelocity = Vec3::Zero();  ///< rad/s, world

  Vec6 twist() const {
    Vec6 v;
    v << linearVelocity, angularVelocity;
    return v;
  }
};

/// The rotation vector (axis * angle, angle in [0, pi]) of a rotation.
inline Vec3 rotationVector(const Mat3& rotation) {
  const Eigen::AngleAxisd aa(rotation);
  double angle = aa.angle();
  Vec3 axis = aa.axis();
  if (angle > M_PI) {  // AngleAxis may return (2 pi - a) about -axis
    angle = 2.0 * M_PI - angle;
    axis = -axis;
  }
  return angle * axis;
}

/// The 6-D displacement that takes pose `worldFromA` to `worldFromB`: (pB - pA, rotvec(RB RA^T)), world axes.
inline Vec6 poseDifference(const Rigid& worldFromA, const Rigid& worldFromB) {
  Vec6 d;
  d.head<3>() = worldFromB.translation() - worldFromA.translation();
  d.tail<3>() = rotationVector(worldFromB.linear() * worldFromA.linear().transpose());
  return d;
}

/// The rotation exp(rotationVector) (a rotation vector in world axes).
inline Mat3 rotationFromVector(const Vec3& rotationVectorInWorld) {
  const double angle = rotationVectorInWorld.norm();
  if (angle < 1e-300) return Mat3::Identity();
  return Eigen::AngleAxisd(angle, rotationVectorInWorld / angle).toRotationMatrix();
}

/// The pose moved by a 6-D displacement (translation, rotation vector about the body origin, world axes).
inline Rigid displacePose(const Rigid& worldFromBody, const Vec6& displacement) {
  Rigid out = Rigid::Identity();
  const Quat q = Quat(rotationFromVector(displacement.tail<3>()) * worldFromBody.linear()).normalized();
  out.linear() = q.toRotationMatrix();
  out.translation() = worldFromBody.translation() + displacement.head<3>();
  return out;
}

/// Interpolates two poses: positions linearly, orientations by slerp. t in [0, 1].
inline Rigid interpolatePose(const Rigid& a, const Rigid& b, double t) {
  const Quat qa(a.linear());
  const Quat qb(b.linear());
  Rigid out = Rigid::Identity();
  out.linear() = qa.slerp(t, qb).normalized().toRotationMatrix();
  out.translation() = a.translation() + t * (b.translation() - a.translation());
  return out;
}

/// World-axes inertia of a body whose inertia in its own axes is diagonal.
inline Mat3 worldInertia(const Rigid& worldFromBody, const Vec3& inertiaDiagonalInBody) {
  const Mat3 r = worldFromBody.linear();
  return r * inertiaDiagonalInBody.asDiagonal() * r.transpose();
}

/// The 6x6 block-diagonal mass matrix diag(m I, I_world).
inline Mat6 massMatrix(double mass, const Mat3& inertiaInWorld) {
  Mat6 m = Mat6::Zero();
  m.topLeftCorner<3, 3>() = mass * Mat3::Identity();
  m.bottomRightCorner<3, 3>() = inertiaInWorld;
  return m;
}

}  // namespace sdfccd::haptics
