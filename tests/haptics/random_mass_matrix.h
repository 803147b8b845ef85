// A random 6x6 mass matrix of the god-object's kind for the QP tests (contact_qp_test.cpp, friction_qp_test.cpp):
// m I on the translation (m in [0.1, 5]), a random symmetric positive definite 3x3 inertia on the rotation.
#pragma once

#include <random>

#include "sdfccd/haptics/spatial_types.h"

namespace sdfccd::haptics::test {

inline Mat6 randomMassMatrix(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> pos(0.1, 5.0);
  Eigen::Matrix3d a;
  for (int i = 0; i < 9; ++i) a(i / 3, i % 3) = u(rng);
  Mat6 m = Mat6::Zero();
  m.topLeftCorner<3, 3>() = pos(rng) * Eigen::Matrix3d::Identity();
  m.bottomRightCorner<3, 3>() = a * a.transpose() + 0.05 * Eigen::Matrix3d::Identity();
  return m;
}

}  // namespace sdfccd::haptics::test
