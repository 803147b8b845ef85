/// @file
/// @brief Stick–slip anchors (friction_anchor.h) against analytic answers: a held point keeps its anchor bit for bit
/// (no creep over 10,000 steps), a loaded point slips at exactly mu F_n, the 1-DOF block under a tilted load sticks
/// below atan mu and slides at g (sin theta - mu cos theta), and the table keeps, creates and drops anchors as points
/// enter and leave.
#include "sdfccd/response/friction_anchor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

constexpr double kGravity = 9.81;  // m/s^2
const Vec3 kUp = Vec3::UnitZ();

TEST(FrictionAnchor, ForceIsElasticBelowTheCapAndExactlyMuFnAbove) {
  FrictionSettings settings;
  settings.friction = 0.4;
  settings.tangentialStiffness = 1000.0;
  settings.tangentialDamping = 0.0;
  // Stretch 1 mm along x (plus a normal offset, which carries no tangential force): 1 N < 0.4 * 5 N.
  TangentialForce held = tangentialForce(Vec3(0.001, 0, -0.002), Vec3::Zero(), kUp, Vec3::Zero(), 5.0, settings);
  EXPECT_EQ(held.state, FrictionState::Stick);
  EXPECT_NEAR((held.force - Vec3(-1.0, 0, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((held.stretch - Vec3(0.001, 0, 0)).norm(), 0.0, 1e-18);
  // Stretch 1 cm diagonal: 10 N > 2 N, capped along -s.
  const Vec3 s = 0.01 * Vec3(0.6, 0.8, 0.0);
  TangentialForce slid = tangentialForce(s, Vec3::Zero(), kUp, Vec3(1, 0, 7), 5.0, settings);
  EXPECT_EQ(slid.state, FrictionState::Slip);
  EXPECT_NEAR(slid.force.norm(), 0.4 * 5.0, 1e-14);
  EXPECT_NEAR(slid.force.normalized().dot(-s.normalized()), 1.0, 1e-15);
  EXPECT_NEAR(slid.force.dot(kUp), 0.0, 1e-15);
  // Damping adds along -v_t; no normal force, no friction.
  settings.tangentialDamping = 2.0;
  const TangentialForce damped = tangentialForce(Vec3::Zero(), Vec3::Zero(), kUp, Vec3(0.5, 0, 3), 5.0, settings);
  EXPECT_NEAR((damped.force - Vec3(-1.0, 0, 0)).norm(), 0.0, 1e-15);
  const TangentialForce free = tangentialForce(s, Vec3::Zero(), kUp, Vec3(1, 0, 0), -3.0, settings);
  EXPECT_EQ(free.force, Vec3::Zero());
}

TEST(FrictionAnchor, SlipDragsTheAnchorToTheCoulombLimit) {
  FrictionSettings settings;
  settings.friction = 0.5;
  settings.tangentialStiffness = 2000.0;
  const Vec3 anchor(0.1, 0.2, -0.001);
  // Below: the anchor stays bit for bit.
  const AnchorSlip held = slipAnchor(anchor + Vec3(0.0004, 0, 0.003), anchor, kUp, 2.0, settings);
  EXPECT_EQ(held.state, FrictionState::Stick);
  EXPECT_EQ(held.anchorInField, anchor);
  // Above: k_t |s| = mu F_n afterwards, along the old stretch; the anchor's normal offset is kept.
  const Vec3 point = anchor + Vec3(0.003, -0.004, 0.002);
  const AnchorSlip slid = slipAnchor(point, anchor, kUp, 2.0, settings);
  EXPECT_EQ(slid.state, FrictionState::Slip);
  const Vec3 stretch = point - slid.anchorInField - kUp * kUp.dot(point - slid.anchorInField);
  EXPECT_NEAR(settings.tangentialStiffness * stretch.norm(), 0.5 * 2.0, 1e-12);
  EXPECT_NEAR(stretch.normalized().dot(Vec3(0.6, -0.8, 0)), 1.0, 1e-12);
  EXPECT_EQ(slid.anchorInField.z(), anchor.z());
  // Then the force at the same pose is exactly mu F_n.
  EXPECT_NEAR(tangentialForce(point, slid.anchorInField, kUp, Vec3::Zero(), 2.0, settings).force.norm(), 1.0, 1e-12);
  // No normal force: the anchor follows the point.
  EXPECT_NEAR(
      (slipAnchor(point, anchor, kUp, 0.0, settings).anchorInField - Vec3(point.x(), point.y(), anchor.z())).norm(),
      0.0, 1e-15);
}

TEST(FrictionAnchor, SettingsRejectNegativeAndNonFiniteValues) {
  FrictionSettings settings;
  EXPECT_NO_THROW(settings.validate());
  settings.friction = -0.1;
  EXPECT_THROW(settings.validate(), Error);
  settings.friction = std::nan("");
  EXPECT_THROW(settings.validate(), Error);
  settings = FrictionSettings{};
  settings.tangentialStiffness = -1.0;
  EXPECT_THROW(settings.validate(), Error);
  settings = FrictionSettings{};
  settings.tangentialDamping = std::numeric_limits<double>::infinity();
  EXPECT_THROW(settings.validate(), Error);
}

TEST(FrictionAnchorTable, KeepsCreatesAndDropsAnchorsAsPointsEnterAndLeave) {
  FrictionAnchorTable table;
  auto entry = [](int point, double x) { return AnchorContact{point, Vec3(x, point, 0)}; };
  AnchorMatchResult r = table.match({entry(1, 0.1), entry(3, 0.3), entry(5, 0.5)});
  EXPECT_EQ(r.created, 3);
  EXPECT_EQ(r.kept + r.dropped, 0);
  // Points 3 and 5 stay (their anchors keep last step's positions), 4 and 7 enter, 1 leaves.
  r = table.match({entry(3, 9.0), entry(4, 0.4), entry(5, 9.0), entry(7, 0.7)});
  EXPECT_EQ(r.kept, 2);
  EXPECT_EQ(r.created, 2);
  EXPECT_EQ(r.dropped, 1);
  ASSERT_EQ(table.size(), 4u);
  const int points[] = {3, 4, 5, 7};
  const double xs[] = {0.3, 0.4, 0.5, 0.7};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(table.anchors()[i].point, points[i]);
    EXPECT_EQ(table.anchors()[i].anchorInField.x(), xs[i]);
  }
  EXPECT_EQ(table.find(1), nullptr);
  // Point 1 comes back: a fresh anchor at its new entry, not the old one.
  table.beginMatch();
  EXPECT_EQ(table.matchNext(1, Vec3(2, 0, 0)), 0u);
  EXPECT_EQ(table.matchNext(7, Vec3(9, 0, 0)), 1u);
  r = table.endMatch();
  EXPECT_EQ(r.created, 1);
  EXPECT_EQ(r.kept, 1);
  EXPECT_EQ(r.dropped, 3);
  EXPECT_EQ(table.find(1)->anchorInField.x(), 2.0);
  EXPECT_EQ(table.find(7)->anchorInField.x(), 0.7);
  // Unsorted or repeated contacts are refused; an empty step drops everything.
  EXPECT_THROW(table.match({entry(2, 0), entry(2, 0)}), Error);
  EXPECT_THROW(table.match({entry(4, 0), entry(3, 0)}), Error);
  EXPECT_THROW(table.match({entry(-1, 0)}), Error);
  table.match({entry(2, 0)});
  EXPECT_EQ(table.match({}).dropped, 1);
  EXPECT_EQ(table.size(), 0u);
}

// A 1 kg block on the plane z = 0 under gravity tilted by theta (the incline), resting on `points` shell points
// that share F_n = m g cos theta; one tangential degree of freedom x, symplectic Euler at 1 ms. Each step the
// contacts are matched (a point listed in `absent(step)` is out of contact), sampled at the step's start,
// integrated, and the anchors updated at the end pose.
struct Block {
  double mass = 1.0;      // kg
  double x = 0.0;         // m, along the slope (downhill +)
  double v = 0.0;         // m/s
  double totalK = 1.0e5;  // N/m, all points
  double dt = 1.0e-3;     // s
  int points = 4;
  FrictionAnchorTable table;

  template <class Absent>
  void run(double theta, double mu, int steps, Absent absent) {
    const double zeta = 1.0;  // critical damping of the tangential spring
    FrictionSettings settings;
    settings.friction = mu;
    for (int step = 0; step < steps; ++step) {
      std::vector<AnchorContact> contacts;
      for (int p = 0; p < points; ++p) {
        if (!absent(step, p)) contacts.push_back({p, Vec3(x, 0, 0)});
      }
      table.match(contacts);
      const double n = static_cast<double>(contacts.size());
      settings.tangentialStiffness = totalK / n;
      settings.tangentialDamping = 2.0 * zeta * std::sqrt(totalK * mass) / n;
      const double normalForce = mass * kGravity * std::cos(theta) / n;
      double force = mass * kGravity * std::sin(theta);
      for (std::size_t i = 0; i < contacts.size(); ++i) {
        force +=
            tangentialForce(Vec3(x, 0, 0), table.anchors()[i].anchorInField, kUp, Vec3(v, 0, 0), normalForce, settings)
                .force.x();
      }
      v += force / mass * dt;
      x += v * dt;
      for (std::size_t i = 0; i < contacts.size(); ++i)
        table.updateAnchor(i, Vec3(x, 0, 0), kUp, normalForce, settings);
    }
  }
};

TEST(FrictionAnchorBlock, HeldBelowAtanMuWithoutCreepOver10000Steps) {
  for (double mu : {0.3, 0.5, 0.8}) {
    const double theta = std::atan(mu) - 2.0 * kPi / 180.0;
    Block block;
    block.run(theta, mu, 1000, [](int, int) { return false; });
    const std::vector<FrictionAnchor> anchors = block.table.anchors();
    const double settled = block.x;
    block.run(theta, mu, 10000, [](int, int) { return false; });
    // The sudden load overshoots in its first milliseconds (a step load on a spring), which may slip the anchors
    // by a fraction of the deflection; from then on they hold bit for bit and the block does not move.
    for (std::size_t i = 0; i < anchors.size(); ++i) {
      EXPECT_EQ(block.table.anchors()[i].anchorInField, anchors[i].anchorInField);
      EXPECT_LT(anchors[i].anchorInField.norm(), block.mass * kGravity / block.totalK);
    }
    EXPECT_NEAR(block.x, settled, 1e-15) << mu;
    EXPECT_NEAR(block.x - anchors[0].anchorInField.x(), block.mass * kGravity * std::sin(theta) / block.totalK, 1e-12)
        << mu;
    EXPECT_NEAR(block.v, 0.0, 1e-12);
  }
}

TEST(FrictionAnchorBlock, SlidesAboveAtanMuAtTheCoulombAcceleration) {
  for (double mu : {0.3, 0.5, 0.8}) {
    for (double extra : {3.0, 10.0}) {
      const double theta = std::atan(mu) + extra * kPi / 180.0;
      const double expected = kGravity * (std::sin(theta) - mu * std::cos(theta));
      Block block;
      block.run(theta, mu, 500, [](int, int) { return false; });
      const double v0 = block.v;
      block.run(theta, mu, 1000, [](int, int) { return false; });
      EXPECT_NEAR((block.v - v0) / 1.0, expected, 0.01 * expected) << mu << " " << extra;
    }
  }
}

TEST(FrictionAnchorBlock, SlidesAtTheCoulombAccelerationWhilePointsEnterAndLeave) {
  // 8 points; each step one of them (in turn) is out of contact and comes back with a fresh anchor.
  const double mu = 0.5;
  const double theta = 40.0 * kPi / 180.0;
  const double expected = kGravity * (std::sin(theta) - mu * std::cos(theta));  // 2.548 m/s^2
  Block block;
  block.points = 8;
  auto absent = [](int step, int p) { return step % 8 == p; };
  block.run(theta, mu, 500, absent);
  const double v0 = block.v;
  block.run(theta, mu, 1000, absent);
  EXPECT_NEAR(block.v - v0, expected, 0.01 * expected);
  EXPECT_EQ(block.table.size(), 7u);
}

}  // namespace
}  // namespace sdfccd
