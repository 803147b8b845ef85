/// @file
/// @brief Conversions at the Bullet border (STYLE.md 5: double in the core, Bullet's btScalar outside) and the
/// pose interpolation of time-of-impact clamping. Private to sdfccd::bullet.
#pragma once

#include <LinearMath/btMatrix3x3.h>
#include <LinearMath/btTransform.h>
#include <LinearMath/btVector3.h>

#include "sdfccd/math_types.h"

namespace sdfccd::detail {

inline Vec3 toVec3(const btVector3& v) {
  return Vec3(v.x(), v.y(), v.z());
}
inline Mat3 toMat3(const btMatrix3x3& m) {
  Mat3 out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out(r, c) = m[r][c];
  }
  return out;
}
inline btVector3 toBt(const Vec3& v) {
  return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z()));
}

inline Rigid toRigid(const btTransform& t) {
  Rigid r = Rigid::Identity();
  const btQuaternion q = t.getRotation();
  r.linear() = Quat(q.w(), q.x(), q.y(), q.z()).normalized().toRotationMatrix();
  r.translation() = toVec3(t.getOrigin());
  return r;
}

inline btTransform toBt(const Rigid& r) {
  const Quat q(r.linear());
  return btTransform(btQuaternion(btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w())),
                     toBt(Vec3(r.translation())));
}

/// The pose at fraction t of the step: translation lerped, rotation slerped.
inline Rigid interpolatePose(const Rigid& start, const Rigid& end, double t) {
  Rigid r = Rigid::Identity();
  r.linear() = Quat(start.linear()).slerp(t, Quat(end.linear())).toRotationMatrix();
  r.translation() = start.translation() + t * (end.translation() - start.translation());
  return r;
}

}  // namespace sdfccd::detail
