/// @file
/// @brief ContactQpSolver::solveFriction: the god-object's contact problem with Coulomb friction on a linearised
/// pyramid, as a quasi-static Stewart-Trinkle LCP solved by Lemke's method (see contact_qp.h for the choice).
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sdfccd/haptics/contact_qp.h"
#include "sdfccd/math_types.h"
#include "solver/mass_cholesky.h"

namespace sdfccd::haptics {

namespace {

using Vec3d = Eigen::Vector3d;

constexpr int kMaxFrictionFaces = 64;

/// An orthonormal tangent basis (t1, t2) of the unit normal n, fixed by n alone (deterministic).
void tangentBasis(const Vec3d& n, Vec3d& t1, Vec3d& t2) {
  Eigen::Index axis = 0;
  n.cwiseAbs().minCoeff(&axis);
  t1 = n.cross(Vec3d::Unit(axis)).normalized();
  t2 = n.cross(t1);
}

/// The generalized direction of a force `f` applied at handle `r`: [f; r x f].
Vec6 wrenchOf(const Vec3d& f, const Vec3d& r) {
  Vec6 w;
  w.head<3>() = f;
  w.tail<3>() = r.cross(f);
  return w;
}

}  // namespace

void ContactQpSolver::solveFriction(const Mat6& massMatrix, const std::vector<Vec3d>& normalsIntoObstacle,
                                    const std::vector<Vec3d>& handles, const Vec6& unconstrained,
                                    const ContactQpSettings& settings, ContactQpResult& outResult) {
  const int m = static_cast<int>(normalsIntoObstacle.size());
  outResult = ContactQpResult{};
  outResult.multipliers.assign(static_cast<std::size_t>(m), 0.0);
  outResult.frictionForces.assign(static_cast<std::size_t>(m), Vec3d::Zero());
  auto fail = [&] {
    outResult.state = ContactQpState::Failed;
    outResult.acceleration.setZero();
    std::fill(outResult.multipliers.begin(), outResult.multipliers.end(), 0.0);
    std::fill(outResult.frictionForces.begin(), outResult.frictionForces.end(), Vec3d::Zero());
    outResult.activeCount = 0;
  };
  const double mu = settings.friction;
  const int faces = settings.frictionFaces;
  if (static_cast<int>(handles.size()) != m || !(mu >= 0.0) || !std::isfinite(mu) || faces < 3 ||
      faces > kMaxFrictionFaces || !massMatrix.allFinite() || !unconstrained.allFinite())
    return fail();
  for (int k = 0; k < m; ++k)
    if (!normalsIntoObstacle[static_cast<std::size_t>(k)].allFinite() ||
        !handles[static_cast<std::size_t>(k)].allFinite())
      return fail();
  Eigen::LLT<Mat6> llt;
  if (!factorMassMatrix(massMatrix, llt)) return fail();
  const Vec6 yU = llt.matrixU() * unconstrained;
  const double yNorm = yU.norm();
  if (yNorm == 0.0) return;
  if (m == 0) {
    outResult.acceleration = unconstrained;
    return;
  }

  // Normal columns g_k = L^{-1} J_k^T, normalized as in the frictionless solve; zero normals are dropped.
  Eigen::Matrix<double, 6, Eigen::Dynamic> gT(6, m);
  std::vector<Vec3d> unitNormals(static_cast<std::size_t>(m));
  for (int k = 0; k < m; ++k) {
    const Vec3d& n = normalsIntoObstacle[static_cast<std::size_t>(k)];
    const double len = n.norm();
    unitNormals[static_cast<std::size_t>(k)] = len > 0.0 ? Vec3d(n / len) : Vec3d::Zero();
    gT.col(k) = wrenchOf(unitNormals[static_cast<std::size_t>(k)], handles[static_cast<std::size_t>(k)]);
  }
  llt.matrixL().solveInPlace(gT);
  setColumns(gT, settings.zeroRowTolerance);
  const int kept = static_cast<int>(m_columns.cols());
  if (kept == 0) {
    outResult.acceleration = unconstrained;
    return;
  }

  // Unknowns, each scaled by its contact's 1 / ||g_k|| and by ||y_u|| (the LCP is then of order one):
  // lambda_k at k, beta_kj at kept + k p + j, gamma_k at kept (1 + p) + k. C = [g_k | -h_kj] (6 x kept (1 + p)).
  const int p = faces;
  const int forces = kept * (1 + p);
  const int n = kept * (p + 2);
  m_directions.resize(6, forces);
  m_directions.leftCols(kept) = m_columns;
  m_tangents.resize(static_cast<std::size_t>(kept * p));
  for (int c = 0; c < kept; ++c) {
    const std::size_t k = static_cast<std::size_t>(m_rowOfColumn[static_cast<std::size_t>(c)]);
    Vec3d t1, t2;
    tangentBasis(unitNormals[k], t1, t2);
    for (int j = 0; j < p; ++j) {
      const double angle = 2.0 * kPi * j / p;
      const Vec3d d = std::cos(angle) * t1 + std::sin(angle) * t2;
      m_tangents[static_cast<std::size_t>(c * p + j)] = d;
      Vec6 h = wrenchOf(d, handles[k]);
      llt.matrixL().solveInPlace(h);
      m_directions.col(kept + c * p + j) = -m_rowScale[static_cast<std::size_t>(c)] * h;
    }
  }
  // [w_lambda; w_beta] = C^T C [lambda; beta] - C^T y_u/|y_u| + [0; E gamma];  w_gamma = mu lambda - E^T beta.
  m_lcpMatrix.setZero(n, n);
  m_lcpMatrix.topLeftCorner(forces, forces).noalias() = m_directions.transpose() * m_directions;
  m_lcpQ.setZero(n);
  m_lcpQ.head(forces).noalias() = -(m_directions.transpose() * (yU / yNorm));
  for (int c = 0; c < kept; ++c) {
    const int gamma = forces + c;
    m_lcpMatrix(gamma, c) = mu;
    for (int j = 0; j < p; ++j) {
      const int beta = kept + c * p + j;
      m_lcpMatrix(beta, gamma) = 1.0;
      m_lcpMatrix(gamma, beta) = -1.0;
    }
  }
  int pivots = 0;
  const LcpStatus status = m_lemke.solve(m_lcpMatrix, m_lcpQ, LcpSettings{}, m_lcpZ, pivots);
  outResult.iterations = pivots;
  if (status != LcpStatus::Solved) return fail();

  // y = y_u - sum g lambda + sum h beta (in scaled units), a = L^{-T} y.
  const Vec6 y = yNorm * (yU / yNorm - m_directions * m_lcpZ.head(forces));
  for (int c = 0; c < kept; ++c) {
    const double scale = yNorm * m_rowScale[static_cast<std::size_t>(c)];
    const std::size_t k = static_cast<std::size_t>(m_rowOfColumn[static_cast<std::size_t>(c)]);
    outResult.multipliers[k] = scale * m_lcpZ[c];
    if (outResult.multipliers[k] > 0.0) ++outResult.activeCount;
    Vec3d f = Vec3d::Zero();
    for (int j = 0; j < p; ++j) f += m_lcpZ[kept + c * p + j] * m_tangents[static_cast<std::size_t>(c * p + j)];
    outResult.frictionForces[k] = scale * f;
  }
  outResult.acceleration = llt.matrixU().solve(y);
  if (!outResult.acceleration.allFinite()) return fail();
  for (int k = 0; k < m; ++k) {
    const Vec6 row = wrenchOf(unitNormals[static_cast<std::size_t>(k)], handles[static_cast<std::size_t>(k)]);
    const double len = row.norm();
    if (len > 0.0) outResult.maxViolation = std::max(outResult.maxViolation, row.dot(outResult.acceleration) / len);
  }
  // Sticking (or pressed straight in): the solution is ~0. The Stuck test is geometric (frictionless cone).
  const int maxIterations = settings.maxIterationsPerRow * kept + 30;
  if (y.norm() <= settings.blockedTolerance * yNorm && !markBlocked(settings, maxIterations, outResult)) fail();
}

}  // namespace sdfccd::haptics

namespace sdfccd::haptics {

namespace {

double cross2(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

/// Indices (into `points`) of the convex hull's vertices (Andrew's monotone chain; collinear points dropped).
std::vector<int> convexHull2d(const std::vector<Eigen::Vector2d>& points) {
  const int n = static_cast<int>(points.size());
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const Eigen::Vector2d& pa = points[static_cast<std::size_t>(a)];
    const Eigen::Vector2d& pb = points[static_cast<std::size_t>(b)];
    return pa.x() < pb.x() || (pa.x() == pb.x() && pa.y() < pb.y());
  });
  if (n <= 2) return order;
  std::vector<int> hull(static_cast<std::size_t>(2 * n));
  int k = 0;
  auto at = [&](int i) -> const Eigen::Vector2d& { return points[static_cast<std::size_t>(i)]; };
  for (int pass = 0; pass < 2; ++pass) {      // lower chain, then upper chain
    const int floor = pass == 0 ? 2 : k + 2;  // the upper chain never pops the lower chain's points
    for (int step = 0; step < n; ++step) {
      const int i = order[static_cast<std::size_t>(pass == 0 ? step : n - 1 - step)];
      while (k >= floor &&
             cross2(at(hull[static_cast<std::size_t>(k - 2)]), at(hull[static_cast<std::size_t>(k - 1)]), at(i)) <= 0.0)
        --k;
      hull[static_cast<std::size_t>(k++)] = i;
    }
    --k;  // the last point starts the other chain
  }
  hull.resize(static_cast<std::size_t>(std::max(k, 1)));
  return hull;
}

}  // namespace

void reduceContactPatches(const std::vector<Vec3d>& normals, const std::vector<Vec3d>& handles, double angleTolerance,
                          std::vector<Vec3d>& outNormals, std::vector<Vec3d>& outHandles) {
  outNormals.clear();
  outHandles.clear();
  const std::size_t m = std::min(normals.size(), handles.size());
  const double sinTolerance = std::sin(std::min(angleTolerance, 1.5));
  std::vector<std::uint8_t> taken(m, 0);
  std::vector<int> members;
  std::vector<Eigen::Vector2d> projected;
  for (std::size_t first = 0; first < m; ++first) {
    if (taken[first]) continue;
    const double len = normals[first].norm();
    if (!(len > 0.0) || !std::isfinite(len) || !handles[first].allFinite()) {
      outNormals.push_back(normals[first]);  // left for solveFriction to judge
      outHandles.push_back(handles[first]);
      continue;
    }
    const Vec3d n = normals[first] / len;
    members.clear();
    for (std::size_t k = first; k < m; ++k) {
      if (taken[k]) continue;
      // The sine of the angle (the cosine cannot resolve angles below ~1e-8); the first one always joins.
      const bool same =
          k == first || (normals[k].dot(n) > 0.0 && normals[k].cross(n).norm() <= sinTolerance * normals[k].norm());
      if (same) {
        members.push_back(static_cast<int>(k));
        taken[k] = 1;
      }
    }
    Vec3d t1, t2;
    tangentBasis(n, t1, t2);
    projected.clear();
    for (int k : members)
      projected.emplace_back(handles[static_cast<std::size_t>(k)].dot(t1),
                             handles[static_cast<std::size_t>(k)].dot(t2));
    for (int h : convexHull2d(projected)) {
      outNormals.push_back(n);
      outHandles.push_back(handles[static_cast<std::size_t>(members[static_cast<std::size_t>(h)])]);
    }
  }
}

}  // namespace sdfccd::haptics
