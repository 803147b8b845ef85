/// @file
/// @brief Point shells on analytic surfaces: every point on the surface of the matching analytic field with an
/// outward unit normal, the surface covered at the requested spacing (brute force), the point cap honoured.
#include "sdfccd/shell/analytic_shells.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"

namespace sdfccd {
namespace {

template <class Field>
void expectOnSurface(const PointShell& shell, const Field& field) {
  ASSERT_FALSE(shell.empty());
  EXPECT_NO_THROW(shell.validate());
  for (std::size_t i = 0; i < shell.size(); ++i) {
    EXPECT_NEAR(field.distance(shell.positions[i]), 0.0, 1e-12) << i;
    // Outward: a small step along the normal leaves the solid.
    EXPECT_GT(field.distance(shell.positions[i] + 1e-6 * shell.normals[i]), 0.5e-6) << i;
  }
}

// Random surface points (projected with the field's gradient) lie within `spacing` of a shell point.
template <class Field>
void expectCovered(const PointShell& shell, const Field& field, double spacing) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int n = 0; n < 300; ++n) {
    Vec3 p(u(rng), u(rng), u(rng));
    for (int k = 0; k < 60 && std::abs(field.distance(p)) > 1e-12; ++k) p -= field.distance(p) * field.gradient(p);
    double nearest = 1e9;
    for (const Vec3& q : shell.positions) nearest = std::min(nearest, (p - q).norm());
    EXPECT_LE(nearest, spacing) << p.transpose();
  }
}

TEST(AnalyticShells, BoxPointsOnTheSurfaceCornersIncluded) {
  const Vec3 h(0.5, 0.2, 0.3);
  AnalyticShellSettings settings;
  settings.spacing = 0.1;
  const PointShell shell = boxShell(h, settings);
  // n = (10, 4, 6): all lattice points minus the interior ones.
  EXPECT_EQ(shell.size(), std::size_t(11 * 5 * 7 - 9 * 3 * 5));
  expectOnSurface(shell, BoxField(h));
  expectCovered(shell, BoxField(h), settings.spacing);
  int corners = 0;
  for (std::size_t i = 0; i < shell.size(); ++i) {
    if ((shell.positions[i].cwiseAbs() - h).cwiseAbs().maxCoeff() < 1e-15) {
      ++corners;
      EXPECT_NEAR(std::abs(shell.normals[i].x()), 1.0 / std::sqrt(3.0), 1e-12);
    }
  }
  EXPECT_EQ(corners, 8);
}

TEST(AnalyticShells, SphereAndCapsulePointsOnTheSurface) {
  AnalyticShellSettings settings;
  settings.spacing = 0.08;
  const PointShell ball = sphereShell(0.4, settings);
  EXPECT_NEAR(static_cast<double>(ball.size()), 4.0 * M_PI * 0.16 / 0.0064, 1.0);
  expectOnSurface(ball, SphereField(Vec3::Zero(), 0.4));
  expectCovered(ball, SphereField(Vec3::Zero(), 0.4), settings.spacing);
  for (int axis = 0; axis < 3; ++axis) {
    const PointShell capsule = capsuleShell(0.3, 0.5, axis, settings);
    expectOnSurface(capsule, CapsuleField(0.3, 0.5, axis));
    expectCovered(capsule, CapsuleField(0.3, 0.5, axis), settings.spacing);
  }
  expectOnSurface(capsuleShell(0.3, 0.0, 1, settings), CapsuleField(0.3, 0.0, 1));
}

TEST(AnalyticShells, PointCapAndBadInput) {
  AnalyticShellSettings dense;
  dense.spacing = 1e-4;
  dense.maxPoints = 500;
  EXPECT_LE(boxShell(Vec3(1, 1, 1), dense).size(), 500u);
  EXPECT_LE(sphereShell(1.0, dense).size(), 500u);
  EXPECT_LE(capsuleShell(1.0, 2.0, 2, dense).size(), 500u);
  AnalyticShellSettings bad;
  bad.spacing = 0.0;
  EXPECT_THROW(boxShell(Vec3(1, 1, 1), bad), Error);
  EXPECT_THROW(sphereShell(-1.0, {}), Error);
  EXPECT_THROW(capsuleShell(1.0, 1.0, 5, {}), Error);
  EXPECT_THROW(boxShell(Vec3(1, std::nan(""), 1), {}), Error);
}

}  // namespace
}  // namespace sdfccd
