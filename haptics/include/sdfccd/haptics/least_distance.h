/// @file
/// @brief leastDistanceMove: the smallest move (in a mass metric) that satisfies linear inequalities J p <= b, the
/// push of the god-object by moving obstacles (haptic_obstacles.h).
///
/// @details With M = L L^T and y = L^T p the problem is the least-distance program min ||y|| subject to
/// G y <= b, G = J L^{-T}, solved as Lawson and Hanson do (Solving Least Squares Problems, ch. 23): with
/// E = [-G^T; -b^T] (7 x m) and f = (0, ..., 0, 1), the non-negative least squares u = argmin_{u >= 0} ||E u - f||
/// gives the residual r = E u - f, and y = -r_{1..6} / r_7; r = 0 means the constraints are inconsistent. The
/// contact QP (contact_qp.h) solves the homogeneous case b = 0, a cone; here b != 0 (the gaps to the obstacles'
/// contact level sets), so the feasible set is a polyhedron that need not contain 0. Rows are normalized and b
/// scaled to its largest entry first (the program is homogeneous in b), so the tolerances are relative.
#pragma once

#include <Eigen/Core>

#include "sdfccd/haptics/spatial_types.h"

namespace sdfccd::haptics {

struct LeastDistanceResult {
  Vec6 move = Vec6::Zero();  ///< p (zero when infeasible)
  bool feasible = true;      ///< false: J p <= b has no solution (the tool is squeezed), or no convergence
  int iterations = 0;
};

/// Solves min ||p||_M subject to J p <= b (see the file comment). `mass`: SPD 6x6; `rows`: m x 6; `bound`: m.
LeastDistanceResult leastDistanceMove(const Mat6& mass, const ConstraintRows& rows, const Eigen::VectorXd& bound);

}  // namespace sdfccd::haptics
