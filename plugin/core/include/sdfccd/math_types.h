/// @file
/// @brief Math types of the core: Eigen in double precision.
///
/// @details The core computes in double everywhere (positions, times, integrals); only grid values are stored
/// as float to halve memory. Transforms are named after the frames they connect: `sdfFromShell` maps shell
/// (body) coordinates to SDF coordinates; a point is `pointInSdf`, `pointInWorld`, ...
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace sdfccd {

/// pi to double precision (C++17 has no std::numbers).
inline constexpr double kPi = 3.14159265358979323846;

using Vec3 = Eigen::Vector3d;
using Vec3i = Eigen::Vector3i;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
using Box3 = Eigen::AlignedBox3d;
/// A rigid transform (rotation + translation). Name it `<to>From<from>`, e.g. `worldFromBody`.
using Rigid = Eigen::Isometry3d;

/// A sub-interval [begin, end] of a step, both as fractions in [0, 1] of the step.
struct Interval {
  double begin = 0.0;  ///< fraction of the step where the interval starts
  double end = 0.0;    ///< fraction of the step where the interval ends (>= begin)
};

/// The angle between two unit vectors (rad), accurate near 0 and pi.
inline double angleBetween(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// Every one of the n values finite: Eigen's allFinite() (the same answer) in plain scalar code that inlines, where
/// Eigen's is an out-of-line call, in the per-pair and per-sample checks of a pile's many contacts.
inline bool finiteValues(const double* v, int n) {
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(v[k])) return false;
  }
  return true;
}

}  // namespace sdfccd
