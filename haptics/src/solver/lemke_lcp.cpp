/// @file
/// @brief LemkeSolver: Lemke's complementary pivoting with the lexicographic ratio test (see lemke_lcp.h).
#include "sdfccd/haptics/lemke_lcp.h"

#include <algorithm>
#include <cmath>

namespace sdfccd::haptics {

int LemkeSolver::leavingRow(int column, const LcpSettings& settings) {
  const Eigen::Index n = m_tableau.rows();
  const Eigen::Index rhs = m_tableau.cols() - 1;
  const int z0 = static_cast<int>(2 * n);
  double scale = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) scale = std::max(scale, std::abs(m_tableau(i, column)));
  const double pivotFloor = settings.pivotTolerance * std::max(1.0, scale);
  // The minimum ratio rhs_i / d_i over the rows with d_i > 0 (the basic variables that decrease).
  double best = 0.0;
  bool any = false;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d = m_tableau(i, column);
    if (d <= pivotFloor) continue;
    const double ratio = m_tableau(i, rhs) / d;
    if (!any || ratio < best) best = ratio;
    any = true;
  }
  if (!any) return -1;
  m_ties.clear();
  const double tie = settings.tieTolerance * (1.0 + std::abs(best));
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d = m_tableau(i, column);
    if (d > pivotFloor && m_tableau(i, rhs) / d <= best + tie) m_ties.push_back(static_cast<int>(i));
  }
  // z0 leaving ends the method: prefer it among ties.
  for (int i : m_ties)
    if (m_basis[static_cast<std::size_t>(i)] == z0) return i;
  // Lexicographic rule: compare the rows of B^{-1} (the w columns) divided by d_i, column by column.
  for (Eigen::Index k = 0; k < n && m_ties.size() > 1; ++k) {
    double least = 0.0;
    bool first = true;
    for (int i : m_ties) {
      const double v = m_tableau(i, k) / m_tableau(i, column);
      if (first || v < least) least = v;
      first = false;
    }
    const double slack = settings.tieTolerance * (1.0 + std::abs(least));
    m_ties.erase(std::remove_if(m_ties.begin(), m_ties.end(),
                                [&](int i) { return m_tableau(i, k) / m_tableau(i, column) > least + slack; }),
                 m_ties.end());
  }
  return m_ties.empty() ? -1 : m_ties.front();  // none (a NaN ratio never compares): no blocking row
}

void LemkeSolver::pivot(int row, int column) {
  m_column = m_tableau.col(column);
  m_tableau.row(row) /= m_column[row];
  m_column[row] = 0.0;
  m_tableau.noalias() -= m_column * m_tableau.row(row);
  m_tableau(row, column) = 1.0;
  m_basis[static_cast<std::size_t>(row)] = column;
}

LcpStatus LemkeSolver::solve(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, const LcpSettings& settings,
                             Eigen::VectorXd& z, int& pivots) {
  const Eigen::Index n = q.size();
  pivots = 0;
  z.setZero(n);
  if (m.rows() != n || m.cols() != n || !m.allFinite() || !q.allFinite()) return LcpStatus::BadInput;
  if (n == 0 || q.minCoeff() >= 0.0) return LcpStatus::Solved;  // z = 0, w = q
  // Tableau of w - M z - e z0 = q, the w basic.
  m_tableau.setZero(n, 2 * n + 2);
  m_tableau.leftCols(n).setIdentity();
  m_tableau.middleCols(n, n) = -m;
  m_tableau.col(2 * n).setConstant(-1.0);
  m_tableau.col(2 * n + 1) = q;
  m_basis.resize(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) m_basis[static_cast<std::size_t>(i)] = static_cast<int>(i);
  const int z0 = static_cast<int>(2 * n);

  // z0 enters at the most negative q_i (ties: the lexicographic rule on the row of -e, which is -1 in every
  // row, i.e. on the rows of the identity: the smallest index among the ties).
  Eigen::Index first = 0;
  q.minCoeff(&first);
  int entering = z0;
  int row = static_cast<int>(first);
  const int maxPivots = settings.maxPivotsPerUnknown * static_cast<int>(n) + 50;
  while (true) {
    const int leaving = m_basis[static_cast<std::size_t>(row)];
    pivot(row, entering);
    ++pivots;
    if (leaving == z0) break;
    if (pivots >= maxPivots) return LcpStatus::PivotCap;
    entering = leaving < n ? leaving + static_cast<int>(n) : leaving - static_cast<int>(n);  // the complement
    row = leavingRow(entering, settings);
    if (row < 0) return LcpStatus::Ray;
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    const int v = m_basis[static_cast<std::size_t>(i)];
    if (v >= n && v < 2 * n) z[v - n] = std::max(0.0, m_tableau(i, 2 * n + 1));
  }
  return z.allFinite() ? LcpStatus::Solved : LcpStatus::BadInput;
}

}  // namespace sdfccd::haptics
