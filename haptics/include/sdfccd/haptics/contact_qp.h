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
/// Friction (solveFriction, friction_qp.cpp): Coulomb friction with coefficient mu on a linearised friction
/// pyramid of p faces per contact. The friction force at contact k is f_k = sum_j beta_kj d_kj, beta >= 0, with
/// d_kj = cos(2 pi j / p) t1 + sin(2 pi j / p) t2 the pyramid's edges in the tangent plane and
/// sum_j beta_kj <= mu lambda_k (the polygon inscribed in the circle of radius mu lambda_k). Maximum dissipation
/// picks f_k most opposed to the contact's tangential motion. So a sliding contact's friction force has
/// magnitude between mu lambda cos(pi / p) (motion across a face's middle) and mu lambda (motion along an
/// edge): p = 8 gives [0.924, 1] mu lambda; a contact sticks whenever its tangential load is below
/// mu lambda cos(pi / p) in every direction. The conditions (quasi-static Stewart-Trinkle, with a the
/// displacement per cycle and W = M^{-1}):
///   a = a_u + W (-N^T lambda + D^T beta),
///   0 <= lambda  _|_  -N a >= 0,  0 <= beta  _|_  D a + E gamma >= 0,  0 <= gamma  _|_  mu lambda - E^T beta >= 0
/// form an LCP in (lambda, beta, gamma) that is not a projection any more (the friction bound depends on the
/// unknown normal force, and its matrix is not symmetric), so NNLS cannot express it. We solve it with
/// Lemke's method (lemke_lcp.h): finite, exact up to rounding (KKT residuals at rounding level, which the
/// tests check by brute force), and it always terminates with a solution on this LCP (Stewart & Trinkle
/// 1996). Projected Gauss-Seidel was rejected because it is iterative: a sticking contact would creep by its
/// residual every cycle. A convex relaxation (Anitescu's cone complementarity) was rejected because it lifts a
/// sliding tool off the surface by mu times its slide. A box-constrained dual QP fixes the friction bound from
/// the previous normal force and is exact only at a fixed point. No library: Debian ships neither qpOASES nor
/// OSQP, and a dense Lemke is ~100 lines. Its cost is O(n^2) per pivot with n = contacts * (p + 2), so
/// friction is for contact sets of tens of points (coplanar patches are first reduced to their hulls by the
/// god-object, reduceContactPatches); friction 0 keeps the NNLS solve exactly. A few contacts (the alpha
/// puzzle) stay within the haptic budget; tens of contacts in a tight fit (the peg in its hole) do not, where a
/// revised Lemke (a Schur complement on the few basic z, O(n s) per pivot) would be the next step (`bench haptics`
/// measures both).
///
/// Thread safety: ContactQpSolver holds scratch buffers; use one per thread.
#pragma once

#include <cstdint>
#include <vector>

#include "sdfccd/haptics/lemke_lcp.h"
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
  double friction = 0.0;               ///< Coulomb coefficient mu (>= 0); used by solveFriction only
  int frictionFaces = 8;               ///< p, faces of the friction pyramid (>= 3); see @details
};

/// The answer.
struct ContactQpResult {
  ContactQpState state = ContactQpState::Solved;
  Vec6 acceleration = Vec6::Zero();  ///< a_c: the constrained acceleration (linear; angular)
  std::vector<double> multipliers;   ///< mu_k >= 0 per row of J (0 for inactive or dropped rows)
  int activeCount = 0;               ///< rows with mu_k > 0
  int iterations = 0;                ///< NNLS outer iterations (solveFriction: Lemke pivots)
  bool blocked = false;              ///< the solution is ~0 although a_u is not
  double maxViolation = 0.0;         ///< max_k (J a_c)_k / ||J_k|| (<= ~1e-10 when Solved)
  std::vector<Eigen::Vector3d>
      frictionForces;  ///< solveFriction: f_k per contact (world; M (a_c - a_u) units); else empty

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

  /// The same QP with Coulomb friction (settings.friction, settings.frictionFaces; see @details): contact k
  /// has unit normal `normalsIntoObstacle[k]` and handle `handles[k]` (from the centre of mass, world), i.e.
  /// the row contactRow(n_k, r_k). multipliers are the normal forces lambda_k, frictionForces the f_k, so
  /// M (a_c - a_u) = sum_k G_k^T (f_k - lambda_k n_k) with G_k^T f = [f; r_k x f]. Failed on bad settings.
  void solveFriction(const Mat6& massMatrix, const std::vector<Eigen::Vector3d>& normalsIntoObstacle,
                     const std::vector<Eigen::Vector3d>& handles, const Vec6& unconstrained,
                     const ContactQpSettings& settings, ContactQpResult& outResult);

 private:
  /// Fills m_columns, m_rowOfColumn and m_rowScale with the normalized, non-zero columns of G^T = L^{-1} J^T.
  void setColumns(const Eigen::Matrix<double, 6, Eigen::Dynamic>& gT, double zeroRowTolerance);
  /// With the solution ~0: sets `blocked`, zeroes it, and tells Stuck (the columns positively span R^6).
  /// Returns false when the NNLS of the test fails.
  bool markBlocked(const ContactQpSettings& settings, int maxIterations, ContactQpResult& outResult);
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
  // solveFriction
  LemkeSolver m_lemke;
  Eigen::MatrixXd m_lcpMatrix;
  Eigen::VectorXd m_lcpQ;
  Eigen::VectorXd m_lcpZ;
  Eigen::Matrix<double, 6, Eigen::Dynamic> m_directions;  // [g_k | -h_kj]: normalized normal and tangent columns
  std::vector<Eigen::Vector3d> m_tangents;                // d_kj, world
};

/// Contact-patch reduction for solveFriction: contacts whose normals agree within `angleTolerance` (rad) form a
/// patch; only the vertices of the convex hull of its handles, projected on the patch's tangent plane, are kept
/// (with the patch's first normal). The constraint n . (v + w x r) <= 0 and the contact wrench [f; r x f] are
/// affine in r, so a point inside the hull adds no constraint and no wrench its hull vertices cannot give:
/// frictionless, the answer is the same (tested). With friction it is the same while the patch translates; under
/// a twist about the normal, maximum dissipation acts per point and the hull vertices, farther from the twist
/// axis, resist the twist more than the full patch would (an approximation, stated). Handles that differ along
/// the normal (contacts within the contact threshold) change only the friction's torque arm, by at most that
/// height. Why: a god-object resting a face on a plane has hundreds of contacts (187 in plane-slide.json) and the
/// dense Lemke solve costs O(n^2) per pivot; the hull keeps a handful.
void reduceContactPatches(const std::vector<Eigen::Vector3d>& normals, const std::vector<Eigen::Vector3d>& handles,
                          double angleTolerance, std::vector<Eigen::Vector3d>& outNormals,
                          std::vector<Eigen::Vector3d>& outHandles);

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
