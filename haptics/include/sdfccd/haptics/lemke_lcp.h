/// @file
/// @brief A dense linear complementarity problem (LCP) solver: Lemke's complementary pivoting with the
/// lexicographic ratio test.
///
/// @details Finds z with w = M z + q, w >= 0, z >= 0, w^T z = 0 (n unknowns, M any n x n matrix). Lemke's
/// method adds an artificial variable z0 with covering vector e = (1, ..., 1), starts from the almost
/// complementary basis of the w, and pivots the complement of each leaving variable in until z0 leaves.
/// The lexicographic ratio test (ties broken by the rows of the basis inverse, which the tableau carries in
/// its w columns) keeps it from cycling on degenerate problems, which duplicate and parallel contacts make
/// common here. It terminates with a solution for copositive-plus matrices and for the Stewart-Trinkle
/// friction LCP (Stewart & Trinkle 1996); otherwise it may end on a ray, which is reported.
///
/// Cost: O(n^2) per pivot on the dense tableau (n x (2n + 2)), typically O(n) pivots. Used by the
/// god-object's friction solve (contact_qp.h), where n = contacts * (pyramid faces + 2).
/// Thread safety: the solver holds scratch buffers; use one per thread.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace sdfccd::haptics {

/// Why a Lemke solve ended.
enum class LcpStatus {
  Solved,    ///< z0 left the basis: z is a solution (complementary by construction)
  Ray,       ///< secondary ray: no pivot row (the LCP may have no solution)
  PivotCap,  ///< more pivots than allowed
  BadInput,  ///< sizes differ or a number is not finite
};

/// Tolerances of the pivoting (the problem should be scaled so that M and q are of order one).
struct LcpSettings {
  double pivotTolerance = 1e-11;  ///< column entries at most this (relative to the column) are not pivots
  double tieTolerance = 1e-9;     ///< ratios this close (relative) are ties, broken lexicographically (at 1e-12,
                                  ///< rounding split true ties of degenerate contact sets and ended on false rays)
  int maxPivotsPerUnknown = 20;   ///< pivot cap: maxPivotsPerUnknown * n + 50
};

/// Lemke's method on a dense tableau, reusing its memory across calls.
class LemkeSolver {
 public:
  /// Solves w = M z + q; on Solved, `z` holds the solution (clamped at 0 against rounding). `pivots` counts
  /// the pivots made.
  LcpStatus solve(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, const LcpSettings& settings, Eigen::VectorXd& z,
                  int& pivots);

 private:
  /// The leaving row for entering column `column`: the lexicographic minimum ratio; -1 if none.
  int leavingRow(int column, const LcpSettings& settings);
  /// Gauss-Jordan pivot on (row, column); the variable of `column` becomes basic in `row`.
  void pivot(int row, int column);

  Eigen::MatrixXd m_tableau;  // n x (2n + 2): [w columns | z columns | z0 | rhs]
  std::vector<int> m_basis;   // variable basic in each row: 0..n-1 w, n..2n-1 z, 2n z0
  std::vector<int> m_ties;    // scratch of leavingRow
  Eigen::VectorXd m_column;   // scratch of pivot
};

}  // namespace sdfccd::haptics
