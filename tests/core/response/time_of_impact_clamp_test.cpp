// The time-of-impact clamp's policy and its impact (response/time_of_impact_clamp.h), against closed forms.
#include "sdfccd/response/time_of_impact_clamp.h"

#include <gtest/gtest.h>

namespace sdfccd {
namespace {

ImpactBody ball(double mass, const Vec3& velocity) {
  ImpactBody b;
  b.inverseMass = 1.0 / mass;
  b.inverseInertiaInWorld = Mat3::Identity() * (1.0 / (0.4 * mass * 0.01));
  b.linearVelocity = velocity;
  return b;
}

TEST(TimeOfImpactClamp, PolicyNeverRewindsAKinematicPair) {
  EXPECT_EQ(clampAction(false, false, false), ClampAction::None);
  EXPECT_EQ(clampAction(false, true, false), ClampAction::None);
  EXPECT_EQ(clampAction(true, false, false), ClampAction::Rewind);
  EXPECT_EQ(clampAction(true, true, false), ClampAction::KinematicPush);
  EXPECT_EQ(clampAction(true, false, true), ClampAction::KinematicPush);
}

TEST(TimeOfImpactClamp, HeadOnImpactOnAStaticFieldStopsTheNormalVelocity) {
  ImpactBody shell = ball(2.0, Vec3(0.3, -1.0, 0.0));
  ImpactBody ground;  // static: infinite mass, at rest
  const ImpactResult r = resolveImpact({ImpactPoint{Vec3::Zero(), Vec3::UnitY()}}, shell, ground);
  EXPECT_NEAR(shell.linearVelocity.y(), 0.0, 1e-12);
  EXPECT_NEAR(r.impulseOnShell.y(), 2.0, 1e-12);  // m v
  EXPECT_EQ(ground.linearVelocity, Vec3::Zero());
  EXPECT_EQ(r.activePoints, 1);
}

TEST(TimeOfImpactClamp, ImpactWithRestitutionReflectsTheNormalVelocity) {
  for (const double e : {0.3, 0.6, 1.0}) {
    ImpactBody shell = ball(2.0, Vec3(0.3, -1.0, 0.0));
    ImpactBody ground;
    const ImpactResult r = resolveImpact({ImpactPoint{Vec3::Zero(), Vec3::UnitY()}}, shell, ground, e);
    EXPECT_NEAR(shell.linearVelocity.y(), e * 1.0, 1e-12) << e;
    EXPECT_NEAR(shell.linearVelocity.x(), 0.3, 1e-12) << e;  // the tangential velocity is the friction's
    EXPECT_NEAR(r.impulseOnShell.y(), 2.0 * (1.0 + e), 1e-12) << e;
  }
  // Two equal balls head on, e = 1: they exchange their velocities (momentum and energy kept).
  ImpactBody a = ball(1.0, Vec3(0.0, -1.0, 0.0));
  ImpactBody b = ball(1.0, Vec3::Zero());
  resolveImpact({ImpactPoint{Vec3::Zero(), Vec3::UnitY()}}, a, b, 1.0);
  EXPECT_NEAR(a.linearVelocity.y(), 0.0, 1e-12);
  EXPECT_NEAR(b.linearVelocity.y(), -1.0, 1e-12);
}

TEST(TimeOfImpactClamp, AKinematicFieldsVelocityCounts) {
  // A resting ball hit by a kinematic wall at 1 m/s along x leaves with the wall's normal speed.
  ImpactBody shell = ball(1.0, Vec3::Zero());
  ImpactBody wall;
  wall.linearVelocity = Vec3(1.0, 0.0, 0.0);
  wall.centerOfMass = Vec3(-0.2, 0.0, 0.0);
  resolveImpact({ImpactPoint{Vec3(-0.05, 0, 0), Vec3::UnitX()}}, shell, wall);
  EXPECT_NEAR(shell.linearVelocity.x(), 1.0, 1e-12);
  EXPECT_EQ(wall.linearVelocity, Vec3(1.0, 0.0, 0.0));  // infinite mass keeps its velocity
}

TEST(TimeOfImpactClamp, SeparatingPointsGetNoImpulse) {
  ImpactBody shell = ball(1.0, Vec3(0.0, 0.5, 0.0));
  ImpactBody ground;
  const ImpactResult r = resolveImpact({ImpactPoint{Vec3::Zero(), Vec3::UnitY()}}, shell, ground);
  EXPECT_EQ(r.activePoints, 0);
  EXPECT_EQ(shell.linearVelocity, Vec3(0.0, 0.5, 0.0));
}

TEST(TimeOfImpactClamp, EqualMassesShareTheApproach) {
  ImpactBody a = ball(1.0, Vec3(0.0, -1.0, 0.0));
  ImpactBody b = ball(1.0, Vec3::Zero());
  a.centerOfMass = Vec3(0, 0.1, 0);
  b.centerOfMass = Vec3(0, -0.1, 0);
  resolveImpact({ImpactPoint{Vec3::Zero(), Vec3::UnitY()}}, a, b);
  EXPECT_NEAR(a.linearVelocity.y(), -0.5, 1e-12);
  EXPECT_NEAR(b.linearVelocity.y(), -0.5, 1e-12);
}

TEST(TimeOfImpactClamp, KinematicPushFollowsTheAdvanceAfterTheHit) {
  const Vec3 push = kinematicPushDistance(Vec3(1.0, 0, 0), Vec3::UnitX(), 0.25, 0.001);
  EXPECT_NEAR(push.x(), 0.75e-3, 1e-15);
  EXPECT_EQ(kinematicPushDistance(Vec3(-1.0, 0, 0), Vec3::UnitX(), 0.0, 0.001), Vec3::Zero());  // moving away
}

}  // namespace
}  // namespace sdfccd
