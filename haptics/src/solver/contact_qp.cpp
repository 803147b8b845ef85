/// @file
/// @brief ContactQpSolver: the god-object QP by its dual, a Lawson-Hanson NNLS (paper Section 4.2).
#include "sdfccd/haptics/contact_qp.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "solver/mass_cholesky.h"

namespace sdfccd::haptics {

namespace {

bool allFinite(const Mat6& m, const ConstraintRows& j, const Vec6& a) {
  return m.allFinite() && j.allFinite() && a.allFinite();
}

}  // namespace

bool ContactQpSolver::nnls(const Vec6& b, double tolerance, int maxIterations, Vec6& outResidual, int& outIterations) {
  const int n = static_cast<int>(m_columns.cols());
  m_x.setZero(n);
  m_passive.clear();
  m_inPassive.assign(static_cast<std::size_t>(n), 0);
  m_rejected.assign(static_cast<std::size_t>(n), 0);
  Vec6 r = b;
  outIterations = 0;
  Eigen::Matrix<double, 6, Eigen::Dynamic> aPassive;
  Eigen::VectorXd z;
  for (int it = 0; it < maxIterations; ++it) {
    outIterations = it + 1;
    m_w.noalias() = m_columns.transpose() * r;
    int entering = -1;
    double best = tolerance;
    for (int j = 0; j < n; ++j) {
      if (!m_inPassive[static_cast<std::size_t>(j)] && !m_rejected[static_cast<std::size_t>(j)] && m_w[j] > best) {
        best = m_w[j];
        entering = j;
      }
    }
    if (entering < 0) {
      outResidual = r;
      return true;
    }
    m_passive.push_back(entering);
    m_inPassive[static_cast<std::size_t>(entering)] = 1;
    bool moved = false;
    bool firstInner = true;
    while (!m_passive.empty()) {
      const int k = static_cast<int>(m_passive.size());
      aPassive.resize(6, k);
      for (int c = 0; c < k; ++c) aPassive.col(c) = m_columns.col(m_passive[static_cast<std::size_t>(c)]);
      // Column-pivoted QR: a numerically dependent column gets a zero coefficient instead of a blow-up.
      z = aPassive.colPivHouseholderQr().solve(b);
      if (!z.allFinite()) return false;
      bool allPositive = true;
      for (int c = 0; c < k; ++c) allPositive = allPositive && z[c] > 0.0;
      if (allPositive) {
        for (int c = 0; c < k; ++c) m_x[m_passive[static_cast<std::size_t>(c)]] = z[c];
        moved = true;
        break;
      }
      if (firstInner && z[k - 1] <= 0.0) {
        // Rounding made the entering column useless (in exact arithmetic w > 0 implies z > 0): put it
        // aside until the iterate moves, as Lawson and Hanson advise, instead of cycling on it.
        m_passive.pop_back();
        m_inPassive[static_cast<std::size_t>(entering)] = 0;
        m_rejected[static_cast<std::size_t>(entering)] = 1;
        break;
      }
      firstInner = false;
      // Step from x towards z until the first passive coefficient reaches zero.
      double alpha = 1.0;
      for (int c = 0; c < k; ++c) {
        if (z[c] <= 0.0) {
          const double xc = m_x[m_passive[static_cast<std::size_t>(c)]];
          alpha = std::min(alpha, xc / (xc - z[c]));
        }
      }
      for (int c = 0; c < k; ++c) {
        double& xc = m_x[m_passive[static_cast<std::size_t>(c)]];
        xc += alpha * (z[c] - xc);
      }
      moved = true;
      std::vector<int> kept;
      kept.reserve(m_passive.size());
      for (int idx : m_passive) {
        if (m_x[idx] > 1e-300) {
          kept.push_back(idx);
        } else {
          m_x[idx] = 0.0;
          m_inPassive[static_cast<std::size_t>(idx)] = 0;
        }
      }
      m_passive.swap(kept);
    }
    if (moved) std::fill(m_rejected.begin(), m_rejected.end(), std::uint8_t{0});
    r = b - m_columns * m_x;
  }
  outResidual = r;
  return false;
}

void ContactQpSolver::solve(const Mat6& massMatrix, const ConstraintRows& jacobian, const Vec6& unconstrained,
                            const ContactQpSettings& settings, ContactQpResult& outResult) {
  const int m = static_cast<int>(jacobian.rows());
  outResult.state = ContactQpState::Solved;
  outResult.acceleration.setZero();
  outResult.multipliers.assign(static_cast<std::size_t>(m), 0.0);
  outResult.activeCount = 0;
  outResult.iterations = 0;
  outResult.blocked = false;
  outResult.maxViolation = 0.0;

  auto fail = [&] {
    outResult.state = ContactQpState::Failed;
    outResult.acceleration.setZero();
    std::fill(outResult.multipliers.begin(), outResult.multipliers.end(), 0.0);
    outResult.activeCount = 0;
  };
  if (!allFinite(massMatrix, jacobian, unconstrained)) return fail();
  Eigen::LLT<Mat6> llt;
  if (!factorMassMatrix(massMatrix, llt)) return fail();

  // y = L^T a; G^T = L^{-1} J^T.
  const Vec6 yU = llt.matrixU() * unconstrained;
  const double yNorm = yU.norm();
  if (yNorm == 0.0) return;  // a_u = 0: the optimum is 0; not "blocked", the user asks for nothing
  if (m == 0) {
    outResult.acceleration = unconstrained;
    return;
  }
  const Eigen::Matrix<double, 6, Eigen::Dynamic> gT = llt.matrixL().solve(jacobian.transpose());
  setColumns(gT, settings.zeroRowTolerance);
  const int kept = static_cast<int>(m_columns.cols());
  if (kept == 0) {
    outResult.acceleration = unconstrained;
    return;
  }

  const int maxIterations = settings.maxIterationsPerRow * kept + 30;
  Vec6 y;
  int iterations = 0;
  const bool converged = nnls(yU, settings.optimalityTolerance * yNorm, maxIterations, y, iterations);
  outResult.iterations = iterations;
  if (!converged || !y.allFinite() || !m_x.allFinite()) return fail();
  for (int c = 0; c < kept; ++c) {
    const double mu = m_x[c] * m_rowScale[static_cast<std::size_t>(c)];
    outResult.multipliers[static_cast<std::size_t>(m_rowOfColumn[static_cast<std::size_t>(c)])] = mu;
    if (mu > 0.0) ++outResult.activeCount;
  }
  outResult.acceleration = llt.matrixU().solve(y);
  if (!outResult.acceleration.allFinite()) return fail();
  for (int k = 0; k < m; ++k) {
    const double len = jacobian.row(k).norm();
    if (len > 0.0)
      outResult.maxViolation = std::max(outResult.maxViolation, jacobian.row(k).dot(outResult.acceleration) / len);
  }

  if (y.norm() <= settings.blockedTolerance * yNorm && !markBlocked(settings, maxIterations, outResult)) fail();
}

void ContactQpSolver::setColumns(const Eigen::Matrix<double, 6, Eigen::Dynamic>& gT, double zeroRowTolerance) {
  const int m = static_cast<int>(gT.cols());
  double longest = 0.0;
  for (int k = 0; k < m; ++k) longest = std::max(longest, gT.col(k).norm());
  m_columns.resize(6, m);
  m_rowOfColumn.clear();
  m_rowScale.clear();
  int kept = 0;
  for (int k = 0; k < m; ++k) {
    const double len = gT.col(k).norm();
    if (len <= zeroRowTolerance * longest || len == 0.0) continue;
    m_columns.col(kept++) = gT.col(k) / len;
    m_rowOfColumn.push_back(k);
    m_rowScale.push_back(1.0 / len);
  }
  m_columns.conservativeResize(6, kept);
}

bool ContactQpSolver::markBlocked(const ContactQpSettings& settings, int maxIterations, ContactQpResult& outResult) {
  outResult.blocked = true;
  outResult.acceleration.setZero();
  if (!settings.detectStuck) return true;
  // The feasible cone is {0} exactly when its polar, the cone spanned by the columns, is all of R^6,
  // i.e. when each of +-e_i projects to zero on the feasible cone.
  bool spansAll = true;
  for (int i = 0; i < 12 && spansAll; ++i) {
    Vec6 e = Vec6::Zero();
    e[i % 6] = i < 6 ? 1.0 : -1.0;
    Vec6 r;
    int it = 0;
    if (!nnls(e, settings.optimalityTolerance, maxIterations, r, it)) return false;
    spansAll = r.norm() <= settings.blockedTolerance;
  }
  if (spansAll) outResult.state = ContactQpState::Stuck;
  return true;
}

}  // namespace sdfccd::haptics
