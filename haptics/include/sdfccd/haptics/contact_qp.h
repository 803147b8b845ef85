/// @file
/// @brief The god-object's contact QP (paper Section 4.2): min ||a - a_u||_M^2 subject to J a <= 0.
///
/// @details M (6x6, symmetric positive definite: mass and inertia blocks) and J (m x 6, one row
/// [n_k^T, (r_k x n_k)^T] per contact) give a convex QP whose feasible set {a : J a <= 0} is a polyhedral
/// cone. It always contains a = 0, so the problem is never infeasible; the solution is unique.
///
/// Method: with M = L L^T (Cholesky) and y = L^T a, the problem is the Euclidean projection of
/// y_u = L^T a_u onto the cone C = {y : G y <= 0}, G = J L^{-T}. By Moreau's decomposition,
/// y* = y_u - G^T mu*, where mu* >= 0 solves the non-negative least-squares problem
/// min_{mu >= 0} ||G^T mu - y_u|| (6 equations, m unknowns), and mu* are the Lagrange multipliers of
/// J a <= 0. We solve it with the Lawson-Hanson active-set NNLS. Written by hand because Debian ships neither
/// qpOASES nor an NNLS solver (Eigen 3.4's unsupported NNLS module is not in the Debian package); the
/// passive set never holds more than 6 columns, so each iteration is a 6 x (<= 6) least squares solve.
///
/// Degenerate input policy (decided here, pinned by tests):
/// - Rows of G are normalized (the feasible set does not change); rows with ||G_k|| below
///   settings.zeroRowTolerance are dropped (0 <= 0 always holds) and get mu = 0.
/// - Duplicate and parallel rows are harmless: the projection y* is unique even when mu* is not.
/// - Non-finite input, or M not SPD, or the iteration cap: Failed, with a = 0 (always feasible). Never NaN.
/// - Stuck (the Fig. 13 false negative): the solution is ~0 while a_u is not, and the rows of J positively
///   span R^6, so the feasible set is {0}: no acceleration at all is permitted. A solution ~0 whose
///   feasible cone is larger (pushing straight into a plane) is Solved, with `blocked` set.
///
/// Thread safety: ContactQpSolver holds scratch buffers; use one per thread.
#pragma once

#include <cstdint>
#include <vector>

#include "sdfccd/haptics/spatial_types.h"

namespace sdfccd::haptics {

/// Why the solve ended.
enum class ContactQpState : std::uint8_t {
  Solved,  ///< the optimum was found (it may be a = 0 with `blocked` set)
  Stuck,   ///< the feasible set is {0} while a_u != 0: the god-object cannot move at all (Fig. 13)
  Failed,  ///< non-finite input, M not SPD or no convergence: acceleration is 0
};

/// Tolerances of the solve (dimensionless: they act on row-normalized, M-scaled quantities).
struct ContactQpSettings {
  double optimalityTolerance = 1e-11;  ///< NNLS stops when max_k (G y)_k <= tol * ||y_u||
  double zeroRowTolerance = 1e-12;     ///< rows of G shorter than this (relative to the longest) are dropped
  double blockedTolerance = 1e-9;      ///< ||y*|| <= tol * ||y_u||: the solution counts as zero
  int maxIterationsPerRow = 3;         ///< NNLS outer-iteration cap: maxIterationsPerRow * m + 30
  bool detectStuck = true;             ///< when the solution is ~0, test whether the feasible set is {0}
};

/// The answer.
struct ContactQpResult {
  ContactQpState state = ContactQpState::Solved;
  Vec6 acceleration = Vec6::Zero();  ///< a_c: the constrained acceleration (linear; angular)
  std::vector<double> multipliers;   ///< mu_k >= 0 per row of J (0 for inactive or dropped rows)
  int activeCount = 0;               ///< rows with mu_k > 0
  int iterations = 0;                ///< NNLS outer iterations
  bool blocked = false;              ///< the solution is ~0 although a_u is not
  double maxViolation = 0.0;         ///< max_k (J a_c)_k / ||J_k|| (<= ~1e-10 when Solved)

  bool ok() const { return state != ContactQpState::Failed; }
};

/// Solves the QP, reusing scratch memory across calls (one solver per thread).
class ContactQpSolver {
 public:
  /// `massMatrix`: SPD 6x6. `jacobian`: m x 6 rows J_k (m may be 0). `unconstrained`: a_u.
  /// Never throws on bad numbers: reports Failed.
  void solve(const Mat6& massMatrix, const ConstraintRows& jacobian, const Vec6& unconstrained,
             const ContactQpSettings& settings, ContactQpResult& outResult);

  ContactQpResult solve(const Mat6& massMatrix, const ConstraintRows& jacobian, const Vec6& unconstrained,
                        const ContactQpSettings& settings = {}) {
    ContactQpResult r;
    solve(massMatrix, jacobian, unconstrained, settings, r);
    return r;
  }

 private:
  /// Lawson-Hanson NNLS: min_{x >= 0} ||A x - b|| over the columns of m_columns (6 x n). Returns false
  /// on the iteration cap. outResidual = b - A x.
  bool nnls(const Vec6& b, double tolerance, int maxIterations, Vec6& outResidual, int& outIterations);

  Eigen::Matrix<double, 6, Eigen::Dynamic> m_columns;  // G^T with normalized, non-zero columns
  std::vector<int> m_rowOfColumn;                      // original row of J for each column
  std::vector<double> m_rowScale;                      // 1 / ||G_k|| per kept column
  Eigen::VectorXd m_x;                                 // NNLS unknowns
  Eigen::VectorXd m_w;                                 // NNLS dual: A^T r
  std::vector<int> m_passive;                          // passive (free) set, at most 6 columns
  std::vector<std::uint8_t> m_inPassive;
  std::vector<std::uint8_t> m_rejected;
};

/// One constraint row for a contact: normal `n` (the direction the god-object must not move along,
/// i.e. into the obstacle; unit) and handle `r` from the god-object's centre of mass, both in world.
inline Eigen::Matrix<double, 1, 6> contactRow(const Eigen::Vector3d& normalIntoObstacle,
                                              const Eigen::Vector3d& handleInWorld) {
  Eigen::Matrix<double, 1, 6> row;
  row.head<3>() = normalIntoObstacle.transpose();
  row.tail<3>() = handleInWorld.cross(normalIntoObstacle).transpose();
  return row;
}

}  // namespace sdfccd::haptics
