/// @file
/// @brief leastDistanceMove: the Lawson-Hanson least-distance program by non-negative least squares.
#include "sdfccd/haptics/least_distance.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <vector>

namespace sdfccd::haptics {

namespace {

using Mat7X = Eigen::Matrix<double, 7, Eigen::Dynamic>;
using Vec7 = Eigen::Matrix<double, 7, 1>;

/// Lawson-Hanson active-set NNLS: min_{u >= 0} ||a u - f||. Returns false on the iteration cap.
bool nonNegativeLeastSquares(const Mat7X& a, const Vec7& f, Eigen::VectorXd& u, int& iterations) {
  const Eigen::Index n = a.cols();
  u.setZero(n);
  std::vector<char> passive(static_cast<std::size_t>(n), 0);
  std::vector<Eigen::Index> set;
  const double tolerance = 1e-12;
  const int maxIterations = 3 * static_cast<int>(n) + 30;
  for (iterations = 0; iterations < maxIterations; ++iterations) {
    const Eigen::VectorXd w = a.transpose() * (f - a * u);
    Eigen::Index entering = -1;
    double best = tolerance;
    for (Eigen::Index j = 0; j < n; ++j)
      if (!passive[static_cast<std::size_t>(j)] && w[j] > best) best = w[j], entering = j;
    if (entering < 0) return true;
    passive[static_cast<std::size_t>(entering)] = 1;
    set.push_back(entering);
    for (;;) {
      Eigen::Matrix<double, 7, Eigen::Dynamic> ap(7, static_cast<Eigen::Index>(set.size()));
      for (std::size_t c = 0; c < set.size(); ++c) ap.col(static_cast<Eigen::Index>(c)) = a.col(set[c]);
      const Eigen::VectorXd z = ap.colPivHouseholderQr().solve(f);
      if (!z.allFinite()) return false;
      if (z.minCoeff() > 0.0) {
        u.setZero();
        for (std::size_t c = 0; c < set.size(); ++c) u[set[c]] = z[static_cast<Eigen::Index>(c)];
        break;
      }
      // Step from u towards z until the first passive coefficient reaches zero; drop it (and any other at zero).
      double alpha = 1.0;
      for (std::size_t c = 0; c < set.size(); ++c) {
        const double zc = z[static_cast<Eigen::Index>(c)];
        if (zc <= 0.0) alpha = std::min(alpha, u[set[c]] / (u[set[c]] - zc));
      }
      for (std::size_t c = 0; c < set.size(); ++c) u[set[c]] += alpha * (z[static_cast<Eigen::Index>(c)] - u[set[c]]);
      std::vector<Eigen::Index> kept;
      for (const Eigen::Index j : set) {
        if (u[j] > tolerance) {
          kept.push_back(j);
        } else {
          u[j] = 0.0;
          passive[static_cast<std::size_t>(j)] = 0;
        }
      }
      set.swap(kept);
      if (set.empty()) break;
    }
  }
  return false;
}

}  // namespace

LeastDistanceResult leastDistanceMove(const Mat6& mass, const ConstraintRows& rows, const Eigen::VectorXd& bound) {
  LeastDistanceResult result;
  if (rows.rows() == 0 || bound.minCoeff() >= 0.0) return result;  // p = 0 is feasible
  const Eigen::LLT<Mat6> llt(mass);
  if (llt.info() != Eigen::Success || !rows.allFinite() || !bound.allFinite()) {
    result.feasible = false;
    return result;
  }
  // G = J L^{-T}: row k of G is (L^{-1} J_k^T)^T.
  const Mat6 lower = llt.matrixL();
  const double scale = bound.cwiseAbs().maxCoeff();
  Mat7X e(7, rows.rows());
  for (Eigen::Index k = 0; k < rows.rows(); ++k) {
    const Vec6 g = lower.triangularView<Eigen::Lower>().solve(rows.row(k).transpose());
    const double len = g.norm();
    if (!(len > 0.0)) {
      e.col(k).setZero();  // 0 <= b_k: a zero row constrains nothing when b_k >= 0
      e(6, k) = bound[k] < 0.0 ? 1.0 : 0.0;
      continue;
    }
    e.col(k).head<6>() = -g / len;
    e(6, k) = -bound[k] / (len * scale);
  }
  Vec7 f = Vec7::Zero();
  f[6] = 1.0;
  Eigen::VectorXd u;
  const bool converged = nonNegativeLeastSquares(e, f, u, result.iterations);
  const Vec7 r = e * u - f;
  if (!converged || !(std::abs(r[6]) > 1e-12)) {
    result.feasible = false;
    return result;
  }
  const Vec6 y = -r.head<6>() / r[6] * scale;
  result.move = lower.transpose().triangularView<Eigen::Upper>().solve(y);
  return result;
}

}  // namespace sdfccd::haptics
