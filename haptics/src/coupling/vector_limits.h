/// @file
/// @brief Small vector limits shared by the device emulator and the passivity controller (private to
/// sdfccd::haptics).
#pragma once

#include "sdfccd/haptics/spatial_types.h"
#include "sdfccd/math_types.h"

namespace sdfccd::haptics {

/// `v` scaled down to length `limit` when it is longer (a force or torque saturation).
inline Vec3 clampNorm(const Vec3& v, double limit) {
  const double n = v.norm();
  return n > limit ? Vec3(v * (limit / n)) : v;
}

}  // namespace sdfccd::haptics
