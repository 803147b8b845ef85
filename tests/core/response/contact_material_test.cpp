/// @file
/// @brief Contact material helpers (contact_material.h) against closed forms: zeta(e) and its inverse, a simulated
/// spring-dashpot that rebounds with e, Bullet's combine rules, the effective mass, and the stiffness and damping caps.
#include "sdfccd/response/contact_material.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

TEST(ContactMaterial, DampingRatioFromRestitutionMatchesTheClosedForm) {
  EXPECT_EQ(dampingRatioFromRestitution(0.0), 1.0);  // stated: critical
  EXPECT_EQ(dampingRatioFromRestitution(1.0), 0.0);
  EXPECT_NEAR(dampingRatioFromRestitution(0.5), std::log(2.0) / std::sqrt(kPi * kPi + std::log(2.0) * std::log(2.0)),
              1e-15);
  for (double e : {1e-6, 0.1, 0.3, 0.5, 0.8, 0.99}) {
    const double zeta = dampingRatioFromRestitution(e);
    EXPECT_GT(zeta, 0.0);
    EXPECT_LT(zeta, 1.0);
    EXPECT_NEAR(restitutionFromDampingRatio(zeta), e, 1e-12 * std::max(e, 1e-3)) << e;
  }
  EXPECT_EQ(restitutionFromDampingRatio(1.0), 0.0);
  EXPECT_EQ(restitutionFromDampingRatio(1.5), 0.0);
  EXPECT_THROW(dampingRatioFromRestitution(-0.1), Error);
  EXPECT_THROW(dampingRatioFromRestitution(1.1), Error);
  EXPECT_THROW(dampingRatioFromRestitution(std::nan("")), Error);
  EXPECT_THROW(restitutionFromDampingRatio(-1.0), Error);
}

// A 1 kg mass hits a spring-dashpot (k, c = 2 zeta(e) sqrt(k m)) at 1 m/s and leaves when its penetration
// returns to zero; symplectic Euler at omega dt = 0.005.
double simulatedRebound(double e) {
  const double mass = 1.0;       // kg
  const double stiffness = 1e4;  // N/m, omega = 100/s
  const double damping = 2.0 * dampingRatioFromRestitution(e) * std::sqrt(stiffness * mass);
  const double dt = 5e-5;  // s
  double x = 0.0;          // m, penetration
  double v = 1.0;          // m/s, into the spring
  for (int step = 0; step < 1000000; ++step) {
    v += (-stiffness * x - damping * v) / mass * dt;
    x += v * dt;
    if (x <= 0.0) return -v / 1.0;
  }
  return 0.0;
}

TEST(ContactMaterial, ASimulatedSpringDashpotReboundsWithE) {
  for (double e : {0.1, 0.3, 0.5, 0.8, 0.95}) EXPECT_NEAR(simulatedRebound(e), e, 0.03 * e) << e;
}

TEST(ContactMaterial, CombineRulesAreBullets) {
  EXPECT_DOUBLE_EQ(combineFriction(0.5, 0.4), 0.2);
  EXPECT_EQ(combineFriction(5.0, 4.0), kMaxCombinedFriction);
  EXPECT_DOUBLE_EQ(combineRestitution(0.5, 0.9), 0.45);
  EXPECT_THROW(combineFriction(-0.1, 1.0), Error);
  EXPECT_THROW(combineRestitution(1.0, std::nan("")), Error);
}

TEST(ContactMaterial, EffectiveMassIncludesRotation) {
  // A 2 kg rod-like body, inverse inertia diag(1, 2, 3) /(kg m^2), hit at r = (0, 0.5, 0) along n = x:
  // r x n = (0, 0, -0.5), so 1/m_eff = 1/2 + 0.25 * 3.
  const Mat3 inverseInertia = Vec3(1.0, 2.0, 3.0).asDiagonal();
  EXPECT_NEAR(inverseEffectiveMassTerm(0.5, inverseInertia, Vec3(0, 0.5, 0), Vec3::UnitX()), 1.25, 1e-15);
  EXPECT_EQ(inverseEffectiveMassTerm(0.0, Mat3::Zero(), Vec3(1, 2, 3), Vec3::UnitZ()), 0.0);  // static
  EXPECT_THROW(inverseEffectiveMassTerm(-1.0, Mat3::Zero(), Vec3::Zero(), Vec3::UnitZ()), Error);
}

TEST(ContactMaterial, CapsBoundOmegaDtAndDampingDt) {
  const double dt = 1e-3;
  // Below the caps: K stays, C = 2 zeta sqrt(K m).
  PairResponseCoefficients soft = pairResponseCoefficients(1e5, 1.0, 1.0, dt);
  EXPECT_FALSE(soft.stiffnessCapped);
  EXPECT_FALSE(soft.dampingCapped);
  EXPECT_EQ(soft.stiffnessScale, 1.0);
  EXPECT_NEAR(soft.totalDamping, 2.0 * std::sqrt(1e5), 1e-9);
  EXPECT_NEAR(soft.dampingPerStiffness * soft.totalStiffness, soft.totalDamping, 1e-9);
  // 10 kg on 0.1 kg (m_eff ~ 0.099 kg) at K = 1e5: omega dt = 1.005 > 0.7; K capped to m_eff (0.7/dt)^2.
  const double inverseMass = 1.0 / 10.0 + 1.0 / 0.1;
  PairResponseCoefficients hard = pairResponseCoefficients(1e5, inverseMass, 1.0, dt);
  EXPECT_TRUE(hard.stiffnessCapped);
  EXPECT_NEAR(hard.totalStiffness, maxPairStiffness(inverseMass, dt, 0.7), 1e-9);
  EXPECT_NEAR(std::sqrt(hard.totalStiffness * inverseMass) * dt, 0.7, 1e-12);
  EXPECT_NEAR(hard.stiffnessScale * 1e5, hard.totalStiffness, 1e-9);
  // zeta = 1 at omega dt = 0.7 gives C dt / m_eff = 1.4: the damping cap brings it to 1.
  EXPECT_TRUE(hard.dampingCapped);
  EXPECT_NEAR(hard.totalDamping * dt * inverseMass, 1.0, 1e-12);
  EXPECT_NEAR(hard.totalDamping, maxPairDamping(inverseMass, dt, 1.0), 1e-9);
  // No dynamic body: nothing to cap or damp.
  const PairResponseCoefficients fixed = pairResponseCoefficients(1e5, 0.0, 1.0, dt);
  EXPECT_EQ(fixed.stiffnessScale, 1.0);
  EXPECT_EQ(fixed.totalDamping, 0.0);
}

TEST(ContactMaterial, BadParametersAreRefusedInOneLine) {
  EXPECT_THROW(pairResponseCoefficients(-1.0, 1.0, 1.0, 1e-3), Error);
  EXPECT_THROW(pairResponseCoefficients(1.0, -1.0, 1.0, 1e-3), Error);
  EXPECT_THROW(pairResponseCoefficients(1.0, 1.0, 2.5, 1e-3), Error);
  EXPECT_THROW(pairResponseCoefficients(1.0, 1.0, 1.0, 0.0), Error);
  EXPECT_THROW(pairResponseCoefficients(std::nan(""), 1.0, 1.0, 1e-3), Error);
  StabilityCapSettings caps;
  caps.maxDampingDt = 2.0;
  EXPECT_THROW(caps.validate(), Error);
  caps = {};
  caps.maxOmegaDt = 0.0;
  EXPECT_THROW(caps.validate(), Error);
  try {
    dampingRatioFromRestitution(3.0);
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("restitution"), std::string::npos);
  }
}

}  // namespace
}  // namespace sdfccd
