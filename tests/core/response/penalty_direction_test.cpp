// PenaltyDirection (penalty_model.h): the paper's shell-normal direction against the conservative field-gradient
// direction, on a plane whose closed-form answers are known. A point with a tilted normal sits at depth b in a
// plane that is itself rotated in the world: with FieldGradient the impulse on the shell is k b dt along the
// plane's world normal whatever the point's normal; with ShellNormal it is k b dt along minus the point's normal.
#include <gtest/gtest.h>

#include <cmath>

#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/response/penalty_model.h"

namespace sdfccd {
namespace {

RigidCcdResult insideForTheWholeStep(const Vec3& normalInShell) {
  RigidCcdResult r;
  PointContact c;
  c.point = 0;
  c.state = SegmentState::StartsInside;
  c.fraction = 0.0;
  c.pointNormalInShell = normalInShell;
  c.intervals.append(0.0, 1.0);
  r.contacts.push_back(c);
  r.firstFraction = 0.0;
  return r;
}

PenaltySettings springOnly(PenaltyDirection direction) {
  PenaltySettings s;
  s.stiffness = 1500.0;
  s.damping = 0.0;
  s.enableDamping = false;
  s.enableRotation = false;
  s.direction = direction;
  return s;
}

TEST(PenaltyDirection, FieldGradientPushesAlongThePlaneNormalShellNormalAlongThePoint) {
  const double b = 0.004, dt = 0.002, k = 1500.0;
  const PlaneField plane(Vec3::UnitY(), 0.0);  // phi = y in the field's frame
  // The field's frame is turned 30 degrees about z in the world: its normal in world is R * y.
  Rigid worldFromSdf = Rigid::Identity();
  worldFromSdf.linear() = Eigen::AngleAxisd(M_PI / 6, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 planeNormalInWorld = worldFromSdf.linear() * Vec3::UnitY();
  const FieldMotion fieldBody = FieldMotion::fixed(worldFromSdf);
  // The shell body sits so that its point (at its origin) is at depth b in the plane, not moving.
  const ShellMotion shell = ShellMotion::fixed(Rigid(worldFromSdf * Eigen::Translation3d(0, -b, 0)));
  const Vec3 tiltedNormal = Vec3(0.6, -0.8, 0.0);  // shell frame = world rotation of the field frame here
  const std::vector<Vec3> points = {Vec3::Zero()};
  const RigidCcdResult ccd = insideForTheWholeStep(tiltedNormal);

  const PenaltyResult gradient =
      integratePenalty(points, plane, ccd, shell, fieldBody, dt, springOnly(PenaltyDirection::FieldGradient));
  const Vec3 expectedGradient = k * b * dt * planeNormalInWorld;
  EXPECT_LT((gradient.impulseOnShell - expectedGradient).norm(), 1e-12) << gradient.impulseOnShell.transpose();
  EXPECT_LT((gradient.impulseOnShell + gradient.impulseOnField).norm(), 1e-15);

  const PenaltyResult normal =
      integratePenalty(points, plane, ccd, shell, fieldBody, dt, springOnly(PenaltyDirection::ShellNormal));
  const Vec3 expectedNormal = -k * b * dt * (shell.worldFromShellStart.linear() * tiltedNormal);
  EXPECT_LT((normal.impulseOnShell - expectedNormal).norm(), 1e-12) << normal.impulseOnShell.transpose();
  // The default is the paper's.
  EXPECT_EQ(PenaltySettings{}.direction, PenaltyDirection::ShellNormal);
}

}  // namespace
}  // namespace sdfccd
