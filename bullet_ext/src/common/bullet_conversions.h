/// @file
/// @brief Conversions at the Bullet border (STYLE.md 5: double in the core, Bullet's btScalar outside) and the
/// pose interpolation of time-of-impact clamping. Private to sdfccd::bullet.
#pragma once

#include <LinearMath/btMatrix3x3.h>
#include <LinearMath/btTransform.h>
#include <LinearMath/btVector3.h>

#include "sdfccd/bullet/bullet_pose.h"
#include "sdfccd/math_types.h"

namespace sdfccd::bullet::detail {

// The public conversions (bullet_pose.h) under the names the plugin's sources use.
using sdfccd::bullet::toRigid;
using sdfccd::bullet::toVec3;
inline Mat3 toMat3(const btMatrix3x3& m) {
  Mat3 out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out(r, c) = m[r][c];
  }
  return out;
}
inline btVector3 toBt(const Vec3& v) {
  return toBtVector3(v);
}
inline btTransform toBt(const Rigid& r) {
  return toBtTransform(r);
}

/// The pose at fraction t of the step: translation lerped, rotation slerped.
inline Rigid interpolatePose(const Rigid& start, const Rigid& end, double t) {
  Rigid r = Rigid::Identity();
  r.linear() = Quat(start.linear()).slerp(t, Quat(end.linear())).toRotationMatrix();
  r.translation() = start.translation() + t * (end.translation() - start.translation());
  return r;
}

}  // namespace sdfccd::bullet::detail
