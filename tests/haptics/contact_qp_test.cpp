/// @file
/// @brief ContactQpSolver against brute force (active-set enumeration), KKT checks, degenerate and
/// fully-blocked (paper Fig. 13) cases.
#include "sdfccd/haptics/contact_qp.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <cmath>
#include <limits>
#include <random>

#include "haptics/random_mass_matrix.h"

namespace sdfccd::haptics {
namespace {

Vec6 randomVec(std::mt19937& rng, double scale = 1.0) {
  std::normal_distribution<double> n(0.0, scale);
  Vec6 v;
  for (int i = 0; i < 6; ++i) v[i] = n(rng);
  return v;
}

double objective(const Mat6& m, const Vec6& a, const Vec6& aU) {
  return (a - aU).dot(m * (a - aU));
}

// Brute force: the optimum is the M-projection of a_u onto {J_S a = 0} for its active set S; enumerate every
// subset, keep the feasible candidate with the smallest objective.
Vec6 bruteForce(const Mat6& m, const ConstraintRows& j, const Vec6& aU) {
  const Eigen::LLT<Mat6> llt(m);
  const Vec6 yU = llt.matrixU() * aU;
  const Eigen::Matrix<double, Eigen::Dynamic, 6> g = llt.matrixL().solve(j.transpose()).transpose();
  const int rows = static_cast<int>(j.rows());
  double best = std::numeric_limits<double>::infinity();
  Vec6 bestA = Vec6::Zero();
  for (int mask = 0; mask < (1 << rows); ++mask) {
    Eigen::Matrix<double, Eigen::Dynamic, 6> gs(0, 6);
    for (int k = 0; k < rows; ++k) {
      if (mask & (1 << k)) {
        gs.conservativeResize(gs.rows() + 1, 6);
        gs.row(gs.rows() - 1) = g.row(k);
      }
    }
    Vec6 y = yU;
    if (gs.rows() > 0) {
      Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(gs);
      cod.setThreshold(1e-10);
      y = yU - cod.pseudoInverse() * (gs * yU);
    }
    const Vec6 a = llt.matrixU().solve(y);
    bool feasible = true;
    for (int k = 0; k < rows; ++k) feasible = feasible && j.row(k).dot(a) <= 1e-9 * (1.0 + j.row(k).norm() * a.norm());
    if (!feasible) continue;
    const double f = objective(m, a, aU);
    if (f < best) {
      best = f;
      bestA = a;
    }
  }
  return bestA;
}

// KKT of the convex QP: feasibility, mu >= 0, stationarity M (a - a_u) + J^T mu = 0, complementarity.
void expectKkt(const Mat6& m, const ConstraintRows& j, const Vec6& aU, const ContactQpResult& r) {
  const double scale = 1.0 + aU.norm();
  Vec6 stationarity = m * (r.acceleration - aU);
  for (int k = 0; k < j.rows(); ++k) {
    const double mu = r.multipliers[static_cast<std::size_t>(k)];
    EXPECT_GE(mu, 0.0);
    const double slack = j.row(k).dot(r.acceleration);
    EXPECT_LE(slack, 1e-8 * scale * (1.0 + j.row(k).norm()));
    EXPECT_LE(std::abs(mu * slack), 1e-7 * scale * scale);
    stationarity += mu * j.row(k).transpose();
  }
  EXPECT_LE(stationarity.norm(), 1e-7 * scale * m.norm());
}

TEST(ContactQp, NoContactsGivesTheUnconstrainedAcceleration) {
  ContactQpSolver solver;
  const Vec6 aU = (Vec6() << 1, -2, 3, 0.1, 0.2, -0.3).finished();
  const ContactQpResult r = solver.solve(Mat6::Identity(), ConstraintRows(0, 6), aU);
  EXPECT_EQ(r.state, ContactQpState::Solved);
  EXPECT_TRUE(r.acceleration.isApprox(aU));
  EXPECT_FALSE(r.blocked);
}

TEST(ContactQp, PlaneContactRemovesTheNormalComponentOnly) {
  // Ground below the body: inward normal -y at a handle straight below the centre (no torque arm).
  ConstraintRows j(1, 6);
  j.row(0) = contactRow(Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(0, -0.5, 0));
  const Vec6 aU = (Vec6() << 2, -3, 1, 0, 0, 0).finished();
  ContactQpSolver solver;
  const ContactQpResult r = solver.solve(Mat6::Identity(), j, aU);
  EXPECT_EQ(r.state, ContactQpState::Solved);
  EXPECT_NEAR((r.acceleration - (Vec6() << 2, 0, 1, 0, 0, 0).finished()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(r.multipliers[0], 3.0, 1e-12);
  EXPECT_EQ(r.activeCount, 1);
  // Pulling away: the constraint is inactive.
  const ContactQpResult away = solver.solve(Mat6::Identity(), j, -aU);
  EXPECT_TRUE(away.acceleration.isApprox(-aU));
  EXPECT_EQ(away.multipliers[0], 0.0);
}

TEST(ContactQp, PushingStraightIntoAPlaneIsBlockedNotStuck) {
  ConstraintRows j(1, 6);
  j.row(0) = contactRow(Eigen::Vector3d(0, -1, 0), Eigen::Vector3d::Zero());
  const Vec6 aU = (Vec6() << 0, -4, 0, 0, 0, 0).finished();
  ContactQpSolver solver;
  const ContactQpResult r = solver.solve(Mat6::Identity(), j, aU);
  EXPECT_EQ(r.state, ContactQpState::Solved);
  EXPECT_TRUE(r.blocked);
  EXPECT_EQ(r.acceleration, Vec6::Zero());
}

// Solves one problem: solved, finite, and within 1e-7 (1 + |aU|) of the brute-force answer.
void solveMatchingBruteForce(ContactQpSolver& solver, const Mat6& m, const ConstraintRows& j, const Vec6& aU, int trial,
                             ContactQpResult& out) {
  out = solver.solve(m, j, aU);
  ASSERT_EQ(out.state, ContactQpState::Solved) << "trial " << trial;
  ASSERT_TRUE(out.acceleration.allFinite());
  const Vec6 expected = bruteForce(m, j, aU);
  EXPECT_LE((out.acceleration - expected).norm(), 1e-7 * (1.0 + aU.norm())) << "trial " << trial;
}

TEST(ContactQp, MatchesBruteForceOnRandomSmallProblems) {
  std::mt19937 rng(12345);
  ContactQpSolver solver;
  for (int trial = 0; trial < 3000; ++trial) {
    const int rows = 1 + trial % 6;
    const Mat6 m = test::randomMassMatrix(rng);
    ConstraintRows j(rows, 6);
    for (int k = 0; k < rows; ++k) j.row(k) = randomVec(rng).transpose();
    const Vec6 aU = randomVec(rng, 3.0);
    ContactQpResult r;
    ASSERT_NO_FATAL_FAILURE(solveMatchingBruteForce(solver, m, j, aU, trial, r));
    expectKkt(m, j, aU, r);
  }
}

TEST(ContactQp, DegenerateRowsMatchBruteForce) {
  std::mt19937 rng(777);
  ContactQpSolver solver;
  for (int trial = 0; trial < 2000; ++trial) {
    const Mat6 m = test::randomMassMatrix(rng);
    ConstraintRows j(6, 6);
    const Vec6 base = randomVec(rng);
    j.row(0) = base.transpose();
    j.row(1) = base.transpose();                                             // duplicate
    j.row(2) = 3.5 * base.transpose();                                       // parallel, scaled
    j.row(3) = Vec6::Zero().transpose();                                     // zero row: 0 <= 0
    j.row(4) = (trial % 2 ? Vec6(-base) : randomVec(rng)).transpose();       // opposite: a slab of width 0
    j.row(5) = (0.5 * base + 0.5 * Vec6(j.row(4).transpose())).transpose();  // in the span of others
    const Vec6 aU = randomVec(rng, 2.0);
    ContactQpResult r;
    ASSERT_NO_FATAL_FAILURE(solveMatchingBruteForce(solver, m, j, aU, trial, r));
    EXPECT_EQ(r.multipliers[3], 0.0);
    expectKkt(m, j, aU, r);
  }
}

TEST(ContactQp, ManyContactsSatisfyKkt) {
  std::mt19937 rng(99);
  ContactQpSolver solver;
  for (int trial = 0; trial < 40; ++trial) {
    const int rows = 50 + 10 * trial;
    const Mat6 m = test::randomMassMatrix(rng);
    // Contacts of a body on a bumpy floor: normals mostly -y, handles spread out, so the cone is not {0}.
    ConstraintRows j(rows, 6);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < rows; ++k) {
      const Eigen::Vector3d n = Eigen::Vector3d(0.3 * u(rng), -1.0, 0.3 * u(rng)).normalized();
      j.row(k) = contactRow(n, Eigen::Vector3d(u(rng), -0.5, u(rng)));
    }
    const Vec6 aU = randomVec(rng, 5.0);
    const ContactQpResult r = solver.solve(m, j, aU);
    ASSERT_NE(r.state, ContactQpState::Failed) << "trial " << trial;
    expectKkt(m, j, aU, r);
  }
}

TEST(ContactQp, Fig13AllDirectionsBlockedReportsStuckNeverNaN) {
  std::mt19937 rng(5);
  ContactQpSolver solver;
  for (int trial = 0; trial < 200; ++trial) {
    const Mat6 m = test::randomMassMatrix(rng);
    // +-e_i in a random orthonormal basis positively span R^6; extra random rows change nothing.
    const Eigen::HouseholderQR<Mat6> qr(Mat6::Random());
    const Mat6 q = qr.householderQ();
    const int extra = trial % 20;
    ConstraintRows j(12 + extra, 6);
    for (int i = 0; i < 6; ++i) {
      j.row(2 * i) = q.col(i).transpose();
      j.row(2 * i + 1) = -0.3 * q.col(i).transpose();
    }
    for (int k = 0; k < extra; ++k) j.row(12 + k) = randomVec(rng).transpose();
    const Vec6 aU = randomVec(rng, 4.0);
    const ContactQpResult r = solver.solve(m, j, aU);
    EXPECT_EQ(r.state, ContactQpState::Stuck) << "trial " << trial;
    EXPECT_TRUE(r.blocked);
    EXPECT_TRUE(r.acceleration.allFinite());
    EXPECT_EQ(r.acceleration, Vec6::Zero());
    for (double mu : r.multipliers) EXPECT_TRUE(std::isfinite(mu));
  }
}

TEST(ContactQp, NarrowPassageWithOneFreeDirectionIsNotStuck) {
  // Eleven of the twelve rows +-e_i: without the row +e_5 (a_5 <= 0), the row -e_5 leaves a_5 >= 0 free,
  // every other component is pinned to 0.
  ConstraintRows j(11, 6);
  int row = 0;
  for (int i = 0; i < 12; ++i) {
    if (i == 5) continue;
    Vec6 e = Vec6::Zero();
    e[i % 6] = i < 6 ? 1.0 : -1.0;
    j.row(row++) = e.transpose();
  }
  ContactQpSolver solver;
  const Vec6 aU = (Vec6() << 1, 1, 1, 1, 1, 2).finished();
  const ContactQpResult r = solver.solve(Mat6::Identity(), j, aU);
  EXPECT_EQ(r.state, ContactQpState::Solved);
  EXPECT_NEAR((r.acceleration - (Vec6() << 0, 0, 0, 0, 0, 2).finished()).norm(), 0.0, 1e-12);
  const ContactQpResult back = solver.solve(Mat6::Identity(), j, -aU);
  EXPECT_EQ(back.state, ContactQpState::Solved);  // feasible cone is not {0}: blocked, not stuck
  EXPECT_TRUE(back.blocked);
}

TEST(ContactQp, BadInputFailsWithZeroAcceleration) {
  ContactQpSolver solver;
  ConstraintRows j(2, 6);
  j.setRandom();
  Vec6 aU = Vec6::Ones();
  Mat6 m = Mat6::Identity();
  m(0, 0) = std::numeric_limits<double>::quiet_NaN();
  ContactQpResult r = solver.solve(m, j, aU);
  EXPECT_EQ(r.state, ContactQpState::Failed);
  EXPECT_EQ(r.acceleration, Vec6::Zero());
  m = Mat6::Identity();
  m(3, 3) = -1.0;  // not SPD
  r = solver.solve(m, j, aU);
  EXPECT_EQ(r.state, ContactQpState::Failed);
  EXPECT_EQ(r.acceleration, Vec6::Zero());
  aU[2] = std::numeric_limits<double>::infinity();
  r = solver.solve(Mat6::Identity(), j, aU);
  EXPECT_EQ(r.state, ContactQpState::Failed);
  EXPECT_EQ(r.acceleration, Vec6::Zero());
  j(1, 1) = std::numeric_limits<double>::quiet_NaN();
  r = solver.solve(Mat6::Identity(), j, Vec6::Ones());
  EXPECT_EQ(r.state, ContactQpState::Failed);
  EXPECT_TRUE(r.acceleration.allFinite());
}

TEST(ContactQp, ZeroUnconstrainedAccelerationIsZeroAndNotBlocked) {
  ConstraintRows j(3, 6);
  j.setRandom();
  ContactQpSolver solver;
  const ContactQpResult r = solver.solve(Mat6::Identity(), j, Vec6::Zero());
  EXPECT_EQ(r.state, ContactQpState::Solved);
  EXPECT_EQ(r.acceleration, Vec6::Zero());
  EXPECT_FALSE(r.blocked);
}

}  // namespace
}  // namespace sdfccd::haptics
