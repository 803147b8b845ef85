/// @file
/// @brief The god-object's contact problem with Coulomb friction (ContactQpSolver::solveFriction, Lemke on the
/// quasi-static Stewart-Trinkle LCP): Lemke against brute-force enumeration, friction 0 against the NNLS solve,
/// the optimality conditions checked by brute force on random problems, and analytic plane and V-groove answers.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <random>

#include "haptics/random_mass_matrix.h"
#include "sdfccd/haptics/contact_qp.h"
#include "sdfccd/haptics/lemke_lcp.h"
#include "sdfccd/math_types.h"

namespace sdfccd::haptics {
namespace friction_qp_test {

using V3 = Eigen::Vector3d;

struct Problem {
  Mat6 mass;
  std::vector<V3> normals;  // into the obstacle, unit
  std::vector<V3> handles;
  Vec6 aU;
};

V3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  V3 v(n(rng), n(rng), n(rng));
  return v.normalized();
}

// Contacts mostly below the body (normals with a -y component) so that a downward a_u presses into them.
Problem randomProblem(std::mt19937& rng, int contacts) {
  std::normal_distribution<double> n(0.0, 1.0);
  Problem p;
  p.mass = test::randomMassMatrix(rng);
  for (int k = 0; k < contacts; ++k) {
    V3 normal = randomUnit(rng);
    normal.y() = -std::abs(normal.y()) - 0.3;
    p.normals.push_back(normal.normalized());
    p.handles.push_back(V3(n(rng), n(rng), n(rng)) * 0.5);
  }
  for (int i = 0; i < 6; ++i) p.aU[i] = n(rng);
  p.aU[1] -= 1.0;
  return p;
}

Vec6 wrench(const V3& f, const V3& r) {
  Vec6 w;
  w << f, r.cross(f);
  return w;
}

// The pyramid edges as the header defines them: t1 = n x e_a (a: the axis of the smallest |n_i|), t2 = n x t1.
std::vector<V3> pyramidEdges(const V3& n, int faces) {
  Eigen::Index axis = 0;
  n.cwiseAbs().minCoeff(&axis);
  const V3 t1 = n.cross(V3::Unit(axis)).normalized();
  const V3 t2 = n.cross(t1);
  std::vector<V3> d;
  for (int j = 0; j < faces; ++j)
    d.push_back(std::cos(2.0 * kPi * j / faces) * t1 + std::sin(2.0 * kPi * j / faces) * t2);
  return d;
}

// The dissipation of the friction set mu lambda P at tangential motion v: max over the pyramid of -f . v.
double dissipation(const std::vector<V3>& edges, double bound, const V3& v) {
  double best = -std::numeric_limits<double>::infinity();
  for (const V3& d : edges) best = std::max(best, -d.dot(v));
  return bound * best;
}

// The objective that a_c minimizes with the normal forces held at the solution's (a convex function):
// 1/2 |a - a_u|_M^2 + sum_k dissipation_k(tangential motion of contact k).
double energy(const Problem& p, const ContactQpResult& r, double mu, int faces, const Vec6& a) {
  double e = 0.5 * (a - p.aU).dot(p.mass * (a - p.aU));
  for (std::size_t k = 0; k < p.normals.size(); ++k) {
    const V3 v = a.head<3>() + a.tail<3>().cross(p.handles[k]);
    const V3 vt = v - p.normals[k] * p.normals[k].dot(v);
    e += dissipation(pyramidEdges(p.normals[k], faces), mu * r.multipliers[k], vt);
  }
  return e;
}

// Every condition of the friction problem, checked directly on the answer (independently of the LCP).
void expectFrictionKkt(const Problem& p, const ContactQpResult& r, double mu, int faces, int trial) {
  const double scale = 1.0 + p.aU.norm();
  Vec6 stationarity = p.mass * (r.acceleration - p.aU);
  for (std::size_t k = 0; k < p.normals.size(); ++k) {
    const V3& n = p.normals[k];
    const double lambda = r.multipliers[k];
    const V3& f = r.frictionForces[k];
    const V3 v = r.acceleration.head<3>() + r.acceleration.tail<3>().cross(p.handles[k]);
    const V3 vt = v - n * n.dot(v);
    EXPECT_GE(lambda, 0.0) << trial;
    EXPECT_LE(n.dot(v), 1e-9 * scale) << trial;                             // no penetration
    EXPECT_LE(std::abs(lambda * n.dot(v)), 1e-9 * scale * scale) << trial;  // complementarity
    EXPECT_LE(std::abs(f.dot(n)), 1e-12 * scale) << trial;                  // friction is tangential
    // Inside the pyramid: f . e <= mu lambda cos(pi/p) for each face normal e (between adjacent edges).
    const std::vector<V3> d = pyramidEdges(n, faces);
    for (int j = 0; j < faces; ++j) {
      const V3 e = (d[static_cast<std::size_t>(j)] + d[static_cast<std::size_t>((j + 1) % faces)]).normalized();
      EXPECT_LE(f.dot(e), mu * lambda * std::cos(kPi / faces) + 1e-9 * scale) << trial;
    }
    // Maximum dissipation: -f . v_t equals the largest dissipation the pyramid allows (0 when sticking).
    EXPECT_NEAR(-f.dot(vt), dissipation(d, mu * lambda, vt), 1e-9 * scale * scale) << trial;
    stationarity -= wrench(f - lambda * n, p.handles[k]);
  }
  EXPECT_LE(stationarity.norm(), 1e-9 * scale * p.mass.norm()) << trial;
}

// Brute-force optimality: no feasible a (random directions, random steps, and directions along the active
// constraints' null space) has a lower energy with the normal forces held.
void expectNoBetterNeighbour(const Problem& p, const ContactQpResult& r, double mu, int faces, std::mt19937& rng,
                             int trial) {
  const double e0 = energy(p, r, mu, faces, r.acceleration);
  const double tol = 1e-11 * (1.0 + p.aU.dot(p.mass * p.aU));
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> logStep(-6.0, 0.0);
  Eigen::MatrixXd active(0, 6);
  for (std::size_t k = 0; k < p.normals.size(); ++k) {
    const Vec6 row = wrench(p.normals[k], p.handles[k]);
    if (std::abs(row.dot(r.acceleration)) <= 1e-10 * (1.0 + p.aU.norm())) {
      active.conservativeResize(active.rows() + 1, 6);
      active.row(active.rows() - 1) = row.transpose();
    }
  }
  const Eigen::MatrixXd nullProjector =
      active.rows() == 0 ? Eigen::MatrixXd(Eigen::MatrixXd::Identity(6, 6))
                         : Eigen::MatrixXd(Eigen::MatrixXd::Identity(6, 6) -
                                           active.completeOrthogonalDecomposition().pseudoInverse() * active);
  int tested = 0;
  for (int s = 0; s < 200; ++s) {
    Vec6 delta;
    for (int i = 0; i < 6; ++i) delta[i] = n(rng);
    if (s % 2 == 0) delta = nullProjector * delta;
    const Vec6 a = r.acceleration + std::pow(10.0, logStep(rng)) * (1.0 + p.aU.norm()) * delta;
    bool feasible = true;
    for (std::size_t k = 0; k < p.normals.size(); ++k)
      feasible = feasible && wrench(p.normals[k], p.handles[k]).dot(a) <= 1e-13 * (1.0 + p.aU.norm());
    if (!feasible) continue;
    ++tested;
    EXPECT_GE(energy(p, r, mu, faces, a), e0 - tol) << "trial " << trial;
  }
  EXPECT_GT(tested, 0) << trial;
}

TEST(FrictionQp, LemkeMatchesEnumerationOnRandomPositiveDefiniteLcps) {
  // A positive definite M has exactly one LCP solution: enumerate the 2^n complementary bases for it.
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  LemkeSolver lemke;
  for (int trial = 0; trial < 500; ++trial) {
    const int n = 1 + trial % 6;
    Eigen::MatrixXd a(n, n);
    for (int i = 0; i < n * n; ++i) a(i / n, i % n) = g(rng);
    const Eigen::MatrixXd m = a * a.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n) + 0.3 * (a - a.transpose());
    Eigen::VectorXd q(n);
    for (int i = 0; i < n; ++i) q[i] = g(rng);
    Eigen::VectorXd z;
    int pivots = 0;
    ASSERT_EQ(lemke.solve(m, q, LcpSettings{}, z, pivots), LcpStatus::Solved) << trial;
    Eigen::VectorXd expected;
    int found = 0;
    for (int mask = 0; mask < (1 << n); ++mask) {
      std::vector<int> s;
      for (int i = 0; i < n; ++i)
        if (mask & (1 << i)) s.push_back(i);
      Eigen::VectorXd cand = Eigen::VectorXd::Zero(n);
      if (!s.empty()) {
        Eigen::MatrixXd mss(s.size(), s.size());
        Eigen::VectorXd qs(s.size());
        for (std::size_t i = 0; i < s.size(); ++i) {
          qs[static_cast<Eigen::Index>(i)] = -q[s[i]];
          for (std::size_t j = 0; j < s.size(); ++j) mss(i, j) = m(s[i], s[j]);
        }
        const Eigen::VectorXd zs = mss.fullPivLu().solve(qs);
        for (std::size_t i = 0; i < s.size(); ++i) cand[s[i]] = zs[static_cast<Eigen::Index>(i)];
      }
      const Eigen::VectorXd w = m * cand + q;
      if (cand.minCoeff() >= -1e-12 && w.minCoeff() >= -1e-12) {
        expected = cand;
        ++found;
      }
    }
    ASSERT_EQ(found, 1) << trial;
    EXPECT_LE((z - expected).norm(), 1e-10 * (1.0 + expected.norm())) << trial;
  }
}

TEST(FrictionQp, ZeroFrictionAgreesWithTheNnlsSolve) {
  std::mt19937 rng(2024);
  ContactQpSolver lemkeSolver, nnlsSolver;
  ContactQpSettings s;
  s.friction = 0.0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Problem p = randomProblem(rng, 1 + trial % 12);
    ContactQpResult withLemke, withNnls;
    lemkeSolver.solveFriction(p.mass, p.normals, p.handles, p.aU, s, withLemke);
    ConstraintRows j(static_cast<Eigen::Index>(p.normals.size()), 6);
    for (std::size_t k = 0; k < p.normals.size(); ++k)
      j.row(static_cast<Eigen::Index>(k)) = contactRow(p.normals[k], p.handles[k]);
    nnlsSolver.solve(p.mass, j, p.aU, s, withNnls);
    ASSERT_NE(withLemke.state, ContactQpState::Failed) << trial;
    EXPECT_EQ(withLemke.state, withNnls.state) << trial;
    EXPECT_LE((withLemke.acceleration - withNnls.acceleration).norm(), 1e-10 * (1.0 + p.aU.norm())) << trial;
    for (const V3& f : withLemke.frictionForces) EXPECT_LE(f.norm(), 1e-12 * (1.0 + p.aU.norm()));
  }
}

TEST(FrictionQp, RandomProblemsSatisfyTheFrictionConditionsAndCannotBeImproved) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> muDist(0.05, 1.5);
  ContactQpSolver solver;
  int sticking = 0, sliding = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    const Problem p = randomProblem(rng, 1 + trial % 8);
    ContactQpSettings s;
    s.friction = muDist(rng);
    s.frictionFaces = trial % 3 == 0 ? 4 : (trial % 3 == 1 ? 8 : 5);
    const ContactQpResult r = [&] {
      ContactQpResult out;
      solver.solveFriction(p.mass, p.normals, p.handles, p.aU, s, out);
      return out;
    }();
    ASSERT_NE(r.state, ContactQpState::Failed) << trial;
    ASSERT_EQ(r.frictionForces.size(), p.normals.size());
    if (r.blocked) {
      ++sticking;
      continue;  // a_c was snapped to 0: checked by the analytic tests
    }
    ++sliding;
    expectFrictionKkt(p, r, s.friction, s.frictionFaces, trial);
    expectNoBetterNeighbour(p, r, s.friction, s.frictionFaces, rng, trial);
  }
  EXPECT_GT(sticking, 50);  // both regimes are exercised
  EXPECT_GT(sliding, 500);
}

ContactQpResult solveOne(ContactQpSolver& solver, const Mat6& m, const std::vector<V3>& normals,
                         const std::vector<V3>& handles, const Vec6& aU, double mu, int faces) {
  ContactQpSettings s;
  s.friction = mu;
  s.frictionFaces = faces;
  ContactQpResult r;
  solver.solveFriction(m, normals, handles, aU, s, r);
  return r;
}

V3 totalFriction(const ContactQpResult& r) {
  V3 f = V3::Zero();
  for (const V3& fk : r.frictionForces) f += fk;
  return f;
}

// One contact at the centre on the ground (normal into it: -y), body mass 2: a_u = (t cos phi, -w, t sin phi).
// Normal force 2 w. The pyramid (8 faces) has edges along +-x: there the sliding friction is exactly mu N,
// across a face's middle (phi = pi / 8) it is mu N cos(pi / 8), and in between it lies in that interval.
TEST(FrictionQp, PlaneSticksBelowAndSlidesAboveTheCoulombBound) {
  const double mu = 0.6, w = 3.0, mass = 2.0;
  const int faces = 8;
  const double inscribed = std::cos(kPi / faces);
  const Mat6 m = mass * Mat6::Identity();
  const std::vector<V3> normals{V3(0, -1, 0)}, handles{V3::Zero()};
  ContactQpSolver solver;
  auto request = [&](double t, double phi) {
    return (Vec6() << t * std::cos(phi), -w, t * std::sin(phi), 0, 0, 0).finished();
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi);
  for (int i = 0; i < 50; ++i) {
    // Static: the tangential load is below mu N cos(pi/p) in any direction: no motion, friction balances it.
    const double phi = angle(rng);
    const ContactQpResult r = solveOne(solver, m, normals, handles, request(0.99 * inscribed * mu * w, phi), mu, faces);
    ASSERT_EQ(r.state, ContactQpState::Solved);
    EXPECT_TRUE(r.blocked);
    EXPECT_EQ(r.acceleration, Vec6::Zero());
    EXPECT_NEAR(r.multipliers[0], mass * w, 1e-12);
    EXPECT_NEAR(
        (r.frictionForces[0] + mass * request(0.99 * inscribed * mu * w, phi).head<3>().cwiseProduct(V3(1, 0, 1)))
            .norm(),
        0.0, 1e-12);
  }
  // Sliding along an edge (+x): a = (t - mu w) x, friction exactly -mu N x.
  const double t = 3.0 * mu * w;
  const ContactQpResult edge = solveOne(solver, m, normals, handles, request(t, 0.0), mu, faces);
  ASSERT_EQ(edge.state, ContactQpState::Solved);
  EXPECT_NEAR((edge.acceleration - (Vec6() << t - mu * w, 0, 0, 0, 0, 0).finished()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((edge.frictionForces[0] - V3(-mu * mass * w, 0, 0)).norm(), 0.0, 1e-12);
  // Across a face's middle: friction mu N cos(pi/p), exactly opposite the motion.
  const ContactQpResult face = solveOne(solver, m, normals, handles, request(t, kPi / faces), mu, faces);
  const V3 motion = face.acceleration.head<3>();
  EXPECT_NEAR(face.frictionForces[0].norm(), mu * mass * w * inscribed, 1e-12);
  EXPECT_NEAR(face.frictionForces[0].normalized().dot(motion.normalized()), -1.0, 1e-12);
  EXPECT_NEAR(motion.norm(), t - mu * w * inscribed, 1e-12);
  // Any direction: mu N cos(pi/p) <= |f| <= mu N, and f opposes the motion within the pyramid's half angle.
  for (int i = 0; i < 200; ++i) {
    const ContactQpResult r = solveOne(solver, m, normals, handles, request(t, angle(rng)), mu, faces);
    const double ratio = r.frictionForces[0].norm() / r.multipliers[0];
    EXPECT_GE(ratio, mu * inscribed - 1e-12);
    EXPECT_LE(ratio, mu + 1e-12);
    EXPECT_LE(r.frictionForces[0].normalized().dot(r.acceleration.head<3>().normalized()), -inscribed + 1e-12);
    EXPECT_NEAR(r.acceleration[1], 0.0, 1e-12);
  }
}

// A block in a V-groove along x, walls at alpha = 30 degrees from the vertical, two contacts per wall at the
// centre's height (no torque). Pressed down with w: each wall carries w / (2 sin alpha) (twice w in all), so
// friction holds up to mu w / sin(alpha), twice the flat ground's mu w: the wedge effect.
TEST(FrictionQp, VGrooveHoldsUpToMuWOverSinAlpha) {
  const double mu = 0.3, w = 2.0, alpha = kPi / 6.0;
  const double sa = std::sin(alpha), ca = std::cos(alpha);
  const std::vector<V3> normals{V3(0, -sa, ca), V3(0, -sa, ca), V3(0, -sa, -ca), V3(0, -sa, -ca)};
  const std::vector<V3> handles{V3(1, 0, 0.5), V3(-1, 0, 0.5), V3(1, 0, -0.5), V3(-1, 0, -0.5)};
  const double limit = mu * w / sa;
  ContactQpSolver solver;
  for (const double fraction : {0.55, 0.8, 0.99}) {  // 0.55: would slide on flat ground (0.55 limit > mu w)
    const Vec6 aU = (Vec6() << fraction * limit, -w, 0, 0, 0, 0).finished();
    const ContactQpResult r = solveOne(solver, Mat6::Identity(), normals, handles, aU, mu, 8);
    ASSERT_EQ(r.state, ContactQpState::Solved);
    EXPECT_TRUE(r.blocked) << fraction;
    EXPECT_EQ(r.acceleration, Vec6::Zero());
    EXPECT_NEAR(totalFriction(r).x(), -fraction * limit, 1e-12);
  }
  const Vec6 aU = (Vec6() << 2.0 * limit, -w, 0, 0, 0, 0).finished();
  const ContactQpResult r = solveOne(solver, Mat6::Identity(), normals, handles, aU, mu, 8);
  ASSERT_EQ(r.state, ContactQpState::Solved);
  EXPECT_FALSE(r.blocked);
  EXPECT_NEAR((r.acceleration - (Vec6() << limit, 0, 0, 0, 0, 0).finished()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((totalFriction(r) - V3(-limit, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(r.multipliers[0] + r.multipliers[1], w / (2.0 * sa), 1e-12);
  EXPECT_NEAR(r.multipliers[2] + r.multipliers[3], w / (2.0 * sa), 1e-12);
}

// Degenerate contact sets as the god-object makes them: many points of one face (duplicate and parallel rows).
TEST(FrictionQp, ManyAndDuplicateContactsSatisfyTheFrictionConditions) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ContactQpSolver solver;
  for (int trial = 0; trial < 200; ++trial) {
    Problem p = randomProblem(rng, 2 + trial % 5);
    const std::size_t base = p.normals.size();
    for (int extra = 0; extra < 20; ++extra) {  // copies and points of the same faces
      const std::size_t k = static_cast<std::size_t>(extra) % base;
      p.normals.push_back(p.normals[k]);
      V3 r = p.handles[k];
      if (extra % 2 == 1) r += 0.3 * u(rng) * p.normals[k].unitOrthogonal();
      p.handles.push_back(r);
    }
    const double mu = 0.2 + 0.1 * (trial % 8);
    const ContactQpResult r = solveOne(solver, p.mass, p.normals, p.handles, p.aU, mu, trial % 2 ? 4 : 8);
    ASSERT_NE(r.state, ContactQpState::Failed) << trial;
    if (!r.blocked) expectFrictionKkt(p, r, mu, trial % 2 ? 4 : 8, trial);
  }
}

TEST(FrictionQp, BadSettingsOrInputFailWithZeroAcceleration) {
  ContactQpSolver solver;
  const std::vector<V3> normals{V3(0, -1, 0)}, handles{V3::Zero()};
  const Vec6 aU = (Vec6() << 1, -1, 0, 0, 0, 0).finished();
  for (const double mu : {-0.1, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    const ContactQpResult r = solveOne(solver, Mat6::Identity(), normals, handles, aU, mu, 8);
    EXPECT_EQ(r.state, ContactQpState::Failed);
    EXPECT_EQ(r.acceleration, Vec6::Zero());
  }
  EXPECT_EQ(solveOne(solver, Mat6::Identity(), normals, handles, aU, 0.5, 2).state, ContactQpState::Failed);
  EXPECT_EQ(solveOne(solver, Mat6::Identity(), normals, {}, aU, 0.5, 8).state, ContactQpState::Failed);
  EXPECT_EQ(solveOne(solver, -Mat6::Identity(), normals, handles, aU, 0.5, 8).state, ContactQpState::Failed);
  const std::vector<V3> nanNormal{V3(0, std::nan(""), 0)};
  EXPECT_EQ(solveOne(solver, Mat6::Identity(), nanNormal, handles, aU, 0.5, 8).state, ContactQpState::Failed);
}

// A face on a face: coplanar contacts with one normal reduce to the hull of their handles. Frictionless, the answer
// is the same; with friction, the reduced answer meets every condition on its own set and no contact of the
// full set penetrates (the hull's friction differs only under twist, see contact_qp.h).
TEST(FrictionQp, CoplanarPatchesReduceToTheirHull) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ContactQpSolver solver;
  for (int trial = 0; trial < 40; ++trial) {
    Problem p = randomProblem(rng, 0);
    // Two patches: 15 points of a tilted floor plane and 10 of a side wall, each in its own plane.
    const V3 floorNormal = V3(0.2 * u(rng), -1.0, 0.2 * u(rng)).normalized();
    const V3 wallNormal = V3(1.0, 0.1 * u(rng), 0.1 * u(rng)).normalized();
    for (int i = 0; i < 25; ++i) {
      const V3 n = i < 15 ? floorNormal : wallNormal;
      const V3 r = V3(u(rng), u(rng), u(rng)) * 0.5;
      p.normals.push_back(n);
      p.handles.push_back(r - n * (n.dot(r) - (i < 15 ? 0.4 : 0.3)));  // on the plane n . r = 0.4 (0.3)
    }
    Problem q = p;
    reduceContactPatches(p.normals, p.handles, 1e-9, q.normals, q.handles);
    EXPECT_LT(q.normals.size(), p.normals.size());
    EXPECT_GE(q.normals.size(), 5u);  // two patches: at least a triangle and a segment
    const ContactQpResult fullFree = solveOne(solver, p.mass, p.normals, p.handles, p.aU, 0.0, 8);
    const ContactQpResult reducedFree = solveOne(solver, p.mass, q.normals, q.handles, p.aU, 0.0, 8);
    EXPECT_LE((fullFree.acceleration - reducedFree.acceleration).norm(), 1e-9 * (1.0 + p.aU.norm())) << trial;
    const double mu = 0.2 + 0.05 * (trial % 10);
    const ContactQpResult reduced = solveOne(solver, p.mass, q.normals, q.handles, p.aU, mu, 8);
    ASSERT_EQ(reduced.state, ContactQpState::Solved) << trial;
    if (!reduced.blocked) expectFrictionKkt(q, reduced, mu, 8, trial);
    for (std::size_t k = 0; k < p.normals.size(); ++k)
      EXPECT_LE(wrench(p.normals[k], p.handles[k]).dot(reduced.acceleration), 1e-9 * (1.0 + p.aU.norm())) << trial;
  }
}

}  // namespace friction_qp_test
}  // namespace sdfccd::haptics
