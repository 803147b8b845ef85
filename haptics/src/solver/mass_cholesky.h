/// @file
/// @brief The Cholesky factor of a contact problem's mass matrix, shared by the god-object's two solves
/// (contact_qp.cpp, friction_qp.cpp): both work in the metric y = L^T a of M = L L^T.
#pragma once

#include <Eigen/Cholesky>

#include "sdfccd/haptics/spatial_types.h"

namespace sdfccd::haptics {

/// Factors `massMatrix`; false (the solve fails) when it is not symmetric to 1e-9 relative or not positive
/// definite. The caller has checked it finite.
inline bool factorMassMatrix(const Mat6& massMatrix, Eigen::LLT<Mat6>& outFactor) {
  if ((massMatrix - massMatrix.transpose()).cwiseAbs().maxCoeff() > 1e-9 * massMatrix.cwiseAbs().maxCoeff())
    return false;
  outFactor.compute(massMatrix);
  return outFactor.info() == Eigen::Success;
}

}  // namespace sdfccd::haptics
