/// @file
/// @brief 6-vectors and 6x6 matrices of rigid-body haptics: (linear, angular) stacked, in double.
///
/// @details A 6-vector holds the linear part first, then the angular part: an acceleration (a_G, alpha),
/// a velocity (v, omega), a wrench (force, torque). Frames follow the name: `...InWorld`.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace sdfccd::haptics {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
/// m x 6 constraint rows (row-major: one contact per row, appended cheaply).
using ConstraintRows = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;

}  // namespace sdfccd::haptics
