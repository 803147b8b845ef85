/// @file
/// @brief Small Eigen expressions of the hot loops written out component by component, in the very order Eigen
/// evaluates them on this build (so the very bits and the very answers), and forced inline: in the penalty sampling
/// loop and the CCD's point transforms and box tests the compiler left Eigen's out of line, a call per point.
/// Private to the core.
#pragma once

#include <algorithm>

#include "sdfccd/math_types.h"

#if defined(__GNUC__)
#define SDFCCD_FORCE_INLINE inline __attribute__((always_inline))
#else
#define SDFCCD_FORCE_INLINE inline
#endif

namespace sdfccd {
namespace detail {
namespace scalar_ops {

/// m v as Eigen evaluates `Mat3 * Vec3` on this target (Eigen 3.4, SSE2): rows 0 and 1 as one packet, summed left
/// to right, row 2 alone, reduced as m20 v0 + (m21 v1 + m22 v2). Written out because the compiler left Eigen's
/// product out of line in the penalty sampling loop and the CCD's point transforms: the same operations in the same
/// order, so the same bits (checked against Eigen's product on 2e6 random matrices and vectors of mixed magnitudes; the
/// other two associations differ in a third of them). A build that vectorizes Eigen otherwise (another instruction set,
/// EIGEN_DONT_VECTORIZE) would round Eigen's products differently; these keep this order there too.
SDFCCD_FORCE_INLINE Vec3 rotate(const Mat3& m, const Vec3& v) {
  return Vec3((m(0, 0) * v.x() + m(0, 1) * v.y()) + m(0, 2) * v.z(),
              (m(1, 0) * v.x() + m(1, 1) * v.y()) + m(1, 2) * v.z(),
              m(2, 0) * v.x() + (m(2, 1) * v.y() + m(2, 2) * v.z()));
}

/// m^T v as Eigen evaluates `Mat3.transpose() * Vec3` on this target: each row (a column of m) left to right.
SDFCCD_FORCE_INLINE Vec3 rotateBack(const Mat3& m, const Vec3& v) {
  return Vec3((m(0, 0) * v.x() + m(1, 0) * v.y()) + m(2, 0) * v.z(),
              (m(0, 1) * v.x() + m(1, 1) * v.y()) + m(2, 1) * v.z(),
              (m(0, 2) * v.x() + m(1, 2) * v.y()) + m(2, 2) * v.z());
}

/// m v + t as Eigen evaluates `Mat3 * Vec3 + Vec3`: the product as rotate() computes it, then the sum.
SDFCCD_FORCE_INLINE Vec3 transformPoint(const Mat3& m, const Vec3& v, const Vec3& t) {
  const Vec3 r = rotate(m, v);
  return Vec3(r.x() + t.x(), r.y() + t.y(), r.z() + t.z());
}

/// box.contains(p) (Eigen's AlignedBox: min <= p <= max in every axis; false for a NaN).
SDFCCD_FORCE_INLINE bool boxContains(const Box3& box, const Vec3& p) {
  return box.min().x() <= p.x() && box.min().y() <= p.y() && box.min().z() <= p.z() && p.x() <= box.max().x() &&
         p.y() <= box.max().y() && p.z() <= box.max().z();
}

/// p.cwiseMax(box.min()).cwiseMin(box.max()): the nearest point of the box (std::max, then std::min, per axis, as
/// Eigen's scalar coefficient-wise ops; a NaN stays NaN).
SDFCCD_FORCE_INLINE Vec3 clampToBox(const Vec3& p, const Box3& box) {
  return Vec3(std::min(std::max(p.x(), box.min().x()), box.max().x()),
              std::min(std::max(p.y(), box.min().y()), box.max().y()),
              std::min(std::max(p.z(), box.min().z()), box.max().z()));
}

/// Distance from `p` to the box (0 inside): |clampToBox(p) - p|.
SDFCCD_FORCE_INLINE double distanceToBox(const Vec3& p, const Box3& box) {
  return (clampToBox(p, box) - p).norm();
}

}  // namespace scalar_ops
}  // namespace detail
}  // namespace sdfccd
