/// @file
/// @brief The random rigid poses of the paper's Table 3 protocol (Section 3.3): rotation uniform over SO(3),
/// translation uniform in a box. Shared by `sdfccd bench tree` and the core tests that replay the protocol.
#pragma once

#include <random>

#include "sdfccd/math_types.h"

namespace sdfccd::bench {

/// A random rigid transform: rotation uniform (a normalized 4D Gaussian quaternion), translation uniform in `box`.
inline Rigid randomPose(const Box3& box, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Quat q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  Rigid pose = Rigid::Identity();
  pose.linear() = q.toRotationMatrix();
  pose.translation() = box.min() + box.sizes().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
  return pose;
}

}  // namespace sdfccd::bench
