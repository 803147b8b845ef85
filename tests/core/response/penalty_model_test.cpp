// The continuous penalty model (Section 4.1) against closed forms: a point passing linearly through a plane,
// midpoint-rule convergence with a turning normal, a torque about a known handle, damping, the discrete model.
#include "sdfccd/response/penalty_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"

namespace sdfccd {
namespace {

// phi(p) = p.y: the half space y < 0 is inside.
PlaneField testPlane() {
  return PlaneField::ground();
}

RigidCcdResult oneContact(int point, const Vec3& normalInShell, std::initializer_list<Interval> intervals) {
  RigidCcdResult r;
  PointContact c;
  c.point = point;
  c.pointNormalInShell = normalInShell;
  for (const Interval& i : intervals) c.intervals.append(i.begin, i.end);
  c.fraction = intervals.begin()->begin;
  r.contacts.push_back(c);
  r.firstFraction = c.fraction;
  return r;
}

Rigid translation(const Vec3& t) {
  Rigid r = Rigid::Identity();
  r.translation() = t;
  return r;
}

PenaltySettings springOnly(double k, int pieces) {
  PenaltySettings s;
  s.stiffness = k;
  s.damping = 0.0;
  s.enableDamping = false;
  s.subintervals = pieces;
  return s;
}

// A point going from y = a to y = -b during the step, normal -y: I = k dt b^2 / (2 (a + b)) along +y on the
// shell (the depth is linear in t, so the midpoint rule is exact for every N).
TEST(PenaltyModel, PointThroughPlaneMatchesClosedForm) {
  const double a = 0.03, b = 0.01, k = 2000.0, dt = 0.01;
  const std::vector<Vec3> points = {Vec3::Zero()};
  ShellMotion shell;
  shell.worldFromShellStart = translation(Vec3(0, a, 0));
  shell.worldFromShellEnd = translation(Vec3(0, -b, 0));
  const FieldMotion ground = FieldMotion::fixed(Rigid::Identity());
  const RigidCcdResult ccd = oneContact(0, Vec3(0, -1, 0), {{a / (a + b), 1.0}});
  for (int pieces : {1, 5, 17}) {
    const PenaltyResult r = integratePenalty(points, testPlane(), ccd, shell, ground, dt, springOnly(k, pieces));
    const double expected = k * dt * b * b / (2 * (a + b));
    EXPECT_NEAR(r.impulseOnShell.y(), expected, 1e-12 * expected);
    EXPECT_NEAR(r.impulseOnShell.x(), 0.0, 1e-15);
    EXPECT_LT((r.impulseOnShell + r.impulseOnField).norm(), 1e-15);  // action = reaction
    EXPECT_NEAR(r.forceOnShell.y(), expected / dt, 1e-9);            // eq. (5)
    EXPECT_EQ(r.contactCount, 1);
    EXPECT_NEAR(r.maxPenetration, b * (1.0 - 0.5 / pieces / 1.0) * 1.0, b);  // sampled, < b
    EXPECT_LT(r.maxPenetration, b);
    EXPECT_EQ(r.angularImpulseOnShell, Vec3::Zero());  // handle along the normal: no torque
  }
}

// With the body rotating, the normal turns during the step and the integrand is no longer linear: the
// midpoint rule converges at second order towards the limit.
TEST(PenaltyModel, MidpointRuleConvergesWithTurningNormal) {
  const std::vector<Vec3> points = {Vec3(0, -0.5, 0)};
  ShellMotion shell;
  shell.worldFromShellStart = translation(Vec3(0, 0.49, 0));
  shell.worldFromShellEnd = translation(Vec3(0.0, 0.47, 0));
  shell.worldFromShellEnd.linear() = Eigen::AngleAxisd(0.3, Vec3::UnitZ()).toRotationMatrix();
  const FieldMotion ground = FieldMotion::fixed(Rigid::Identity());
  const RigidCcdResult ccd = oneContact(0, Vec3(0, -1, 0), {{0.0, 1.0}});
  const double dt = 0.001;
  auto impulse = [&](int pieces) {
    return integratePenalty(points, testPlane(), ccd, shell, ground, dt, springOnly(1000.0, pieces)).impulseOnShell;
  };
  const Vec3 reference = impulse(20000);
  const double e5 = (impulse(5) - reference).norm();
  const double e20 = (impulse(20) - reference).norm();
  const double e80 = (impulse(80) - reference).norm();
  EXPECT_GT(e5, 0.0);
  EXPECT_LT(e20, e5 / 8.0);  // second order: /16 per factor 4
  EXPECT_LT(e80, e20 / 8.0);
  EXPECT_GT(std::abs(impulse(5).x()), 0.0);  // the turning normal pushes sideways too
}

// A point held at depth 0.01 one unit from the COM: force k * 0.01 up, torque about z = 1 * force.
TEST(PenaltyModel, TorqueAboutKnownHandle) {
  const double k = 500.0, dt = 0.002, depth = 0.01;
  const std::vector<Vec3> points = {Vec3(1.0, -depth, 0.0)};
  const ShellMotion shell = ShellMotion::fixed(Rigid::Identity());  // COM at the origin
  FieldMotion field = FieldMotion::fixed(Rigid::Identity());
  field.centerOfMassInSdf = Vec3(0, -2, 0);
  const RigidCcdResult ccd = oneContact(0, Vec3(0, -1, 0), {{0.0, 1.0}});
  const PenaltyResult r = integratePenalty(points, testPlane(), ccd, shell, field, dt, springOnly(k, 5));
  const double f = k * depth;
  EXPECT_NEAR(r.forceOnShell.y(), f, 1e-9);
  EXPECT_NEAR(r.torqueOnShell.z(), 1.0 * f, 1e-9);
  EXPECT_NEAR(r.torqueOnShell.x(), 0.0, 1e-12);
  // On the field body: force -f y at handle (1, 2 - depth, 0) from its COM: torque z = 1 * (-f).
  EXPECT_NEAR(r.forceOnField.y(), -f, 1e-9);
  EXPECT_NEAR(r.torqueOnField.z(), -f, 1e-9);
  EXPECT_NEAR(r.maxPenetration, depth, 1e-12);

  PenaltySettings noRotation = springOnly(k, 5);
  noRotation.enableRotation = false;
  const PenaltyResult r2 = integratePenalty(points, testPlane(), ccd, shell, field, dt, noRotation);
  EXPECT_EQ(r2.torqueOnShell, Vec3::Zero());
  EXPECT_NEAR(r2.forceOnShell.y(), f, 1e-9);
}

// Damping adds c * v_n while approaching, is off unless enabled, and never pulls.
TEST(PenaltyModel, DampingOpposesApproachAndNeverPulls) {
  const double k = 1000.0, c = 20.0, dt = 0.001, depth = 0.002, speed = 0.5;
  const std::vector<Vec3> points = {Vec3(0, -depth, 0)};
  ShellMotion shell = ShellMotion::fixed(Rigid::Identity());
  shell.velocity.linearStart = shell.velocity.linearEnd = Vec3(0, -speed, 0);  // the poses stay put: pure rate
  const FieldMotion ground = FieldMotion::fixed(Rigid::Identity());
  const RigidCcdResult ccd = oneContact(0, Vec3(0, -1, 0), {{0.0, 1.0}});
  PenaltySettings s = springOnly(k, 5);
  s.damping = c;
  EXPECT_NEAR(integratePenalty(points, testPlane(), ccd, shell, ground, dt, s).forceOnShell.y(), k * depth, 1e-9);
  s.enableDamping = true;
  EXPECT_NEAR(integratePenalty(points, testPlane(), ccd, shell, ground, dt, s).forceOnShell.y(), k * depth + c * speed,
              1e-9);
  shell.velocity.linearStart = shell.velocity.linearEnd = Vec3(0, 10.0, 0);  // separating fast
  EXPECT_NEAR(integratePenalty(points, testPlane(), ccd, shell, ground, dt, s).forceOnShell.y(), 0.0, 1e-12);
}

// Discrete baseline: only the end pose counts; a point that ends outside gives nothing even if it was in.
TEST(PenaltyModel, DiscreteUsesEndDepthOnly) {
  const double k = 2000.0, dt = 0.01;
  const std::vector<Vec3> points = {Vec3::Zero()};
  ShellMotion shell;
  shell.worldFromShellStart = translation(Vec3(0, 0.05, 0));
  shell.worldFromShellEnd = translation(Vec3(0, -0.01, 0));
  const FieldMotion ground = FieldMotion::fixed(Rigid::Identity());
  const RigidCcdResult ccd = oneContact(0, Vec3(0, -1, 0), {{5.0 / 6.0, 1.0}});
  PenaltySettings s = springOnly(k, 5);
  s.model = PenaltyModel::Discrete;
  const PenaltyResult r = integratePenalty(points, testPlane(), ccd, shell, ground, dt, s);
  EXPECT_NEAR(r.forceOnShell.y(), k * 0.01, 1e-9);
  EXPECT_NEAR(r.impulseOnShell.y(), k * 0.01 * dt, 1e-12);
  shell.worldFromShellEnd = translation(Vec3(0, 0.01, 0));
  EXPECT_EQ(integratePenalty(points, testPlane(), ccd, shell, ground, dt, s).contactCount, 0);
}

// Friction (beyond the paper): Coulomb mu |F_n| against the slip above the slip speed, viscous below it;
// off unless enabled.
TEST(PenaltyModel, FrictionOpposesSlip) {
  const double k = 1000.0, dt = 0.001, depth = 0.002, mu = 0.5;
  const std::vector<Vec3> points = {Vec3(0, -depth, 0)};
  ShellMotion shell = ShellMotion::fixed(Rigid::Identity());
  shell.velocity.linearStart = shell.velocity.linearEnd = Vec3(0.3, 0, 0);
  const FieldMotion ground = FieldMotion::fixed(Rigid::Identity());
  const RigidCcdResult ccd = oneContact(0, Vec3(0, -1, 0), {{0.0, 1.0}});
  PenaltySettings s = springOnly(k, 5);
  s.friction = mu;
  EXPECT_NEAR(integratePenalty(points, testPlane(), ccd, shell, ground, dt, s).forceOnShell.x(), 0.0, 1e-15);
  s.enableFriction = true;
  PenaltyResult r = integratePenalty(points, testPlane(), ccd, shell, ground, dt, s);
  EXPECT_NEAR(r.forceOnShell.x(), -mu * k * depth, 1e-9);
  EXPECT_NEAR(r.forceOnShell.y(), k * depth, 1e-9);
  EXPECT_NEAR(r.forceOnField.x(), mu * k * depth, 1e-9);
  shell.velocity.linearStart = shell.velocity.linearEnd = Vec3(0, 0, 0.25 * s.frictionSlipSpeed);
  r = integratePenalty(points, testPlane(), ccd, shell, ground, dt, s);
  EXPECT_NEAR(r.forceOnShell.z(), -0.25 * mu * k * depth, 1e-9);
}

TEST(PenaltyModel, RejectsBadInput) {
  const std::vector<Vec3> points = {Vec3::Zero()};
  const ShellMotion fixed = ShellMotion::fixed(Rigid::Identity());
  const FieldMotion fixedField = FieldMotion::fixed(Rigid::Identity());
  const RigidCcdResult ccd = oneContact(3, Vec3(0, -1, 0), {{0.0, 1.0}});
  EXPECT_THROW(integratePenalty(points, testPlane(), ccd, fixed, fixedField, 0.01, PenaltySettings{}), Error);
  const RigidCcdResult ok = oneContact(0, Vec3(0, -1, 0), {{0.0, 1.0}});
  EXPECT_THROW(integratePenalty(points, testPlane(), ok, fixed, fixedField, 0.0, PenaltySettings{}), Error);
  EXPECT_THROW(integratePenalty(points, testPlane(), ok, fixed, fixedField, NAN, PenaltySettings{}), Error);
  PenaltySettings s;
  s.subintervals = 0;
  EXPECT_THROW(integratePenalty(points, testPlane(), ok, fixed, fixedField, 0.01, s), Error);
}

// checkPenaltyInput's rule, written as its documented checks one by one: true when the input is acceptable.
bool penaltyInputAcceptable(double timestep, const PenaltySettings& s) {
  const auto nonNegativeFinite = [](double x) { return x >= 0.0 && std::isfinite(x); };
  return timestep > 0.0 && std::isfinite(timestep) && nonNegativeFinite(s.stiffness) && nonNegativeFinite(s.damping) &&
         nonNegativeFinite(s.stiffnessPerArea) && s.dampingRatio <= 2.0 && std::isfinite(s.dampingRatio) &&
         s.roleScale > 0.0 && s.roleScale <= 1.0 && s.blendStartCells >= 0.0 && s.blendEndCells > s.blendStartCells &&
         std::isfinite(s.blendEndCells) && s.subintervals >= 1 && nonNegativeFinite(s.friction) &&
         s.frictionSlipSpeed > 0.0 && std::isfinite(s.frictionSlipSpeed);
}

bool penaltyInputCheckPasses(double timestep, const PenaltySettings& s, const RigidCcdResult& ccd,
                             std::size_t pointCount) {
  try {
    checkPenaltyInput(pointCount, ccd, timestep, s);
    return true;
  } catch (const Error&) {
    return false;
  }
}

// Every checked value, set one at a time to each boundary and non-finite value, is accepted exactly when the rule
// accepts it (checkPenaltyInput tests the conditions at once on its fast path, then names the first that fails).
TEST(PenaltyModel, InputChecksAcceptExactlyTheRuleAtEveryBoundary) {
  const double kMax = std::numeric_limits<double>::max();
  const double kInf = std::numeric_limits<double>::infinity();
  const std::vector<double> values = {std::nan(""),
                                      -kInf,
                                      -kMax,
                                      -2.5,
                                      -1e-300,
                                      -0.0,
                                      0.0,
                                      std::numeric_limits<double>::denorm_min(),
                                      0.5,
                                      1.0,
                                      std::nextafter(1.0, 2.0),
                                      2.0,
                                      std::nextafter(2.0, 3.0),
                                      1e300,
                                      kMax,
                                      kInf};
  const RigidCcdResult ok = oneContact(0, Vec3(0, -1, 0), {{0.0, 1.0}});
  const std::vector<double PenaltySettings::*> fields = {
      &PenaltySettings::stiffness,     &PenaltySettings::damping,   &PenaltySettings::stiffnessPerArea,
      &PenaltySettings::dampingRatio,  &PenaltySettings::roleScale, &PenaltySettings::blendStartCells,
      &PenaltySettings::blendEndCells, &PenaltySettings::friction,  &PenaltySettings::frictionSlipSpeed};
  int rejected = 0;
  for (const double value : values) {
    EXPECT_EQ(penaltyInputCheckPasses(value, PenaltySettings{}, ok, 1),
              penaltyInputAcceptable(value, PenaltySettings{}))
        << "timestep " << value;
    for (std::size_t f = 0; f < fields.size(); ++f) {
      PenaltySettings s;
      s.*fields[f] = value;
      const bool expected = penaltyInputAcceptable(0.01, s);
      EXPECT_EQ(penaltyInputCheckPasses(0.01, s, ok, 1), expected) << "field " << f << " = " << value;
      rejected += expected ? 0 : 1;
    }
  }
  EXPECT_GT(rejected, 50);  // the values do probe both sides of every bound
  for (const int pieces : {-1, 0, 1}) {
    PenaltySettings s;
    s.subintervals = pieces;
    EXPECT_EQ(penaltyInputCheckPasses(0.01, s, ok, 1), pieces >= 1);
  }
  // Contact point indices: in range, past the end, negative.
  EXPECT_TRUE(penaltyInputCheckPasses(0.01, PenaltySettings{}, oneContact(2, Vec3(0, -1, 0), {{0.0, 1.0}}), 3));
  EXPECT_FALSE(penaltyInputCheckPasses(0.01, PenaltySettings{}, oneContact(3, Vec3(0, -1, 0), {{0.0, 1.0}}), 3));
  EXPECT_FALSE(penaltyInputCheckPasses(0.01, PenaltySettings{}, oneContact(-1, Vec3(0, -1, 0), {{0.0, 1.0}}), 3));
}

// The per-area law's damping is Rayleigh damping of the pair's elastic wrench (penalty_model.cpp, PairDamping):
// a sphere pressed 2 mm into the ground and spinning in place about a horizontal axis keeps its contact patch
// (W constant), so it gets no damping torque; per-point dampers, pushing on the patch's approaching half and
// pulling on its receding half, brake the spin with beta k omega sum x^2. An approach along the normal is damped
// alike by both.
struct SpinningSphere {
  std::vector<Vec3> points;
  std::vector<double> areas;
  RigidCcdResult ccd;
  ShellMotion shell;
};

SpinningSphere spinningSphere(double radius, double depth, double spacing, const Vec3& omega, const Vec3& velocity) {
  SpinningSphere s;
  const double patch = std::sqrt(2.0 * radius * depth) * 1.2;  // a little wider than the patch
  for (double x = -patch; x <= patch; x += spacing) {
    for (double z = -patch; z <= patch; z += spacing) {
      const double y = -std::sqrt(radius * radius - x * x - z * z);
      PointContact c;
      c.point = static_cast<int>(s.points.size());
      c.state = SegmentState::StartsInside;
      c.fraction = 0.0;
      c.pointNormalInShell = Vec3(x, y, z) / radius;
      c.intervals.append(0.0, 1.0);
      s.points.emplace_back(x, y, z);
      s.areas.push_back(spacing * spacing);
      s.ccd.contacts.push_back(c);
    }
  }
  s.shell = ShellMotion::fixed(translation(Vec3(0, radius - depth, 0)));  // the poses stay put: pure rates
  s.shell.velocity.angularStart = s.shell.velocity.angularEnd = omega;
  s.shell.velocity.linearStart = s.shell.velocity.linearEnd = velocity;
  return s;
}

TEST(PenaltyModel, RayleighDampingLeavesASteadyPatchAlone) {
  const double kA = 1.0e7, beta = 0.01, dt = 0.001, spacing = 2.0e-4;
  PenaltySettings settings = springOnly(0.0, 5);
  settings.enableDamping = true;
  settings.stiffnessPerArea = kA;
  settings.direction = PenaltyDirection::FieldGradient;
  const FieldMotion ground = FieldMotion::fixed(Rigid::Identity());
  auto run = [&](const SpinningSphere& s, bool rayleigh) {
    PenaltyRoleInput input;
    input.areas = &s.areas;
    input.stiffnessPerArea = kA;
    input.dampingPerStiffness = rayleigh ? beta : -1.0;
    PenaltySettings perPoint = settings;
    perPoint.damping = rayleigh ? 0.0 : beta * kA * spacing * spacing;  // the same c_i = beta k_i, per point
    return integratePenalty(s.points, testPlane(), s.ccd, s.shell, ground, dt, perPoint, input);
  };
  const SpinningSphere spinning = spinningSphere(0.05, 0.002, spacing, Vec3(0, 0, -40.0), Vec3::Zero());
  const PenaltyResult pointDampers = run(spinning, false);
  const PenaltyResult rayleigh = run(spinning, true);
  // Unclamped dampers would brake with beta k_A omega int x^2 dA = beta k_A omega pi a^4 / 4 (a^2 = 2 R depth),
  // 0.126 N m here; clamped at zero on the receding half they still brake with 0.074.
  const double a2 = 2.0 * 0.05 * 0.002;
  const double unclamped = beta * kA * 40.0 * 3.14159265358979 * a2 * a2 / 4.0;
  EXPECT_GT(pointDampers.torqueOnShell.z(), 0.5 * unclamped);
  EXPECT_LT(pointDampers.torqueOnShell.z(), unclamped);
  EXPECT_LT(std::abs(rayleigh.torqueOnShell.z()), 0.02 * unclamped);
  PenaltySettings elasticOnly = settings;
  elasticOnly.enableDamping = false;
  PenaltyRoleInput elasticInput;
  elasticInput.areas = &spinning.areas;
  elasticInput.stiffnessPerArea = kA;
  const PenaltyResult elastic = integratePenalty(spinning.points, testPlane(), spinning.ccd, spinning.shell, ground, dt,
                                                 elasticOnly, elasticInput);
  EXPECT_NEAR(rayleigh.forceOnShell.y(), elastic.forceOnShell.y(), 0.01 * elastic.forceOnShell.y());

  const SpinningSphere approaching = spinningSphere(0.05, 0.002, spacing, Vec3::Zero(), Vec3(0, -0.3, 0));
  const PenaltyResult pointApproach = run(approaching, false);
  const PenaltyResult rayleighApproach = run(approaching, true);
  EXPECT_NEAR(rayleighApproach.forceOnShell.y(), pointApproach.forceOnShell.y(), 1e-9 * pointApproach.forceOnShell.y());
  EXPECT_GT(pointApproach.forceOnShell.y(), run(spinning, true).forceOnShell.y());  // the approach is damped
}

}  // namespace
}  // namespace sdfccd
