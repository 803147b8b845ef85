/// @file
/// @brief The penalty sampling loop's vector arithmetic written out component by component (penalty_model.cpp):
/// the very operations, in the very order, of the Eigen expressions they replace on this build, so the same bits,
/// and forced inline (Eigen's are out-of-line calls there). Private to the core.
#pragma once

#include "inline_vector_ops.h"
#include "sdfccd/math_types.h"

namespace sdfccd {
namespace detail {
namespace scalar_ops {

// The sampling loop's helpers are forced inline (SDFCCD_FORCE_INLINE, inline_vector_ops.h): left to the compiler's size
// heuristics, the direction, the friction law and the wrench sums stayed calls, each passing its vectors through
// memory.

/// a + t (b - a), component by component: the very operations (so the very bits) of the Eigen expression, which
/// the compiler left out of line, a call per lerp in the sampling loop (a sample takes up to eight).
SDFCCD_FORCE_INLINE Vec3 lerp(const Vec3& a, const Vec3& b, double t) {
  return Vec3(a.x() + t * (b.x() - a.x()), a.y() + t * (b.y() - a.y()), a.z() + t * (b.z() - a.z()));
}

/// A vector linear in t over the step, a + t (b - a) as lerp computes it, with b - a taken once where it is made
/// (per contact or per role) instead of at every sample: the same subtraction of the same values, the same bits.
struct LinearVec3 {
  Vec3 start = Vec3::Zero();
  Vec3 change = Vec3::Zero();  // end - start

  LinearVec3() = default;
  LinearVec3(const Vec3& a, const Vec3& b) : start(a), change(b.x() - a.x(), b.y() - a.y(), b.z() - a.z()) {}
  SDFCCD_FORCE_INLINE Vec3 at(double t) const {
    return Vec3(start.x() + t * change.x(), start.y() + t * change.y(), start.z() + t * change.z());
  }
};

/// The same for a matrix, entry by entry.
struct LinearMat3 {
  Mat3 start = Mat3::Identity();
  Mat3 change = Mat3::Zero();

  LinearMat3() = default;
  LinearMat3(const Mat3& a, const Mat3& b) : start(a) {
    for (int k = 0; k < 9; ++k) change.data()[k] = b.data()[k] - a.data()[k];
  }
  SDFCCD_FORCE_INLINE Mat3 at(double t) const {
    Mat3 out;
    for (int k = 0; k < 9; ++k) out.data()[k] = start.data()[k] + t * change.data()[k];
    return out;
  }
};

/// io += v, io -= v, io += s v and io -= s v, component by component (the operations of Eigen's compound assignments,
/// one of which is an out-of-line call in the sampling loop).
SDFCCD_FORCE_INLINE void addTo(Vec3& io, const Vec3& v) {
  io = Vec3(io.x() + v.x(), io.y() + v.y(), io.z() + v.z());
}
SDFCCD_FORCE_INLINE void subtractFrom(Vec3& io, const Vec3& v) {
  io = Vec3(io.x() - v.x(), io.y() - v.y(), io.z() - v.z());
}
SDFCCD_FORCE_INLINE void addScaled(Vec3& io, double s, const Vec3& v) {
  io = Vec3(io.x() + s * v.x(), io.y() + s * v.y(), io.z() + s * v.z());
}
SDFCCD_FORCE_INLINE void subtractScaled(Vec3& io, double s, const Vec3& v) {
  io = Vec3(io.x() - s * v.x(), io.y() - s * v.y(), io.z() - s * v.z());
}
/// s v.
SDFCCD_FORCE_INLINE Vec3 scaled(double s, const Vec3& v) {
  return Vec3(s * v.x(), s * v.y(), s * v.z());
}

/// v / length, component by component (length > 0: v's norm).
SDFCCD_FORCE_INLINE Vec3 unit(const Vec3& v, double length) {
  return Vec3(v.x() / length, v.y() / length, v.z() / length);
}

}  // namespace scalar_ops
}  // namespace detail
}  // namespace sdfccd
