/// @file
/// @brief Math types of the core: Eigen in double precision.
///
/// @details The core computes in double everywhere (positions, times, integrals); only grid values are stored
/// as float to halve memory. Transforms are named after the frames they connect: `sdfFromShell` maps shell
/// (body) coordinates to SDF coordinates; a point is `pointInSdf`, `pointInWorld`, ...
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

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

}  // namespace sdfccd
