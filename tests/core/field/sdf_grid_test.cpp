/// @file
/// @brief SdfGrid: trilinear interpolation and gradient against analytic trilinear functions; validation.
#include "sdfccd/field/sdf_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

// A grid sampling f(x,y,z) = a + b x + c y + d z + e xyz, which trilinear interpolation reproduces exactly.
SdfGrid makeTrilinearGrid(const Vec3i& nodes, const Vec3& origin, double h) {
  std::vector<float> v;
  for (int k = 0; k < nodes.z(); ++k)
    for (int j = 0; j < nodes.y(); ++j)
      for (int i = 0; i < nodes.x(); ++i) {
        const Vec3 p = origin + h * Vec3(i, j, k);
        v.push_back(static_cast<float>(0.5 + 0.25 * p.x() - 0.5 * p.y() + 0.125 * p.z()));
      }
  return SdfGrid(nodes, origin, h, std::move(v));
}

TEST(SdfGrid, InterpolatesAffineFunctionExactlyWithGradient) {
  const SdfGrid grid = makeTrilinearGrid({5, 4, 6}, Vec3(-1.0, 0.5, 2.0), 0.25);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Box3 box = grid.box();
  for (int n = 0; n < 200; ++n) {
    const Vec3 p = box.min() + (box.max() - box.min()).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    Vec3 g;
    const double phi = grid.interpolate(p, g);
    EXPECT_NEAR(phi, 0.5 + 0.25 * p.x() - 0.5 * p.y() + 0.125 * p.z(), 1e-6);
    EXPECT_NEAR(g.x(), 0.25, 1e-5);
    EXPECT_NEAR(g.y(), -0.5, 1e-5);
    EXPECT_NEAR(g.z(), 0.125, 1e-5);
  }
}

// interpolate(p) computes the value without the gradient: it must be the two-output form's value bit for bit (the
// CCD, the certificates and the penalty samples mix both), here on a random grid at random points, inside the box,
// on its faces and outside it (clamped).
TEST(SdfGrid, ValueAloneIsTheValueWithGradientBitForBit) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  std::vector<float> values(7 * 5 * 6);
  for (float& v : values) v = value(rng);
  const SdfGrid grid(Vec3i(7, 5, 6), Vec3(-0.3, 0.2, -1.1), 0.37, values);
  const Box3 box = grid.box();
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  for (int n = 0; n < 2000; ++n) {
    Vec3 p = box.min() + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.sizes());
    if (n % 10 == 0) p.x() = box.max().x();  // on a face
    Vec3 g;
    const double both = grid.interpolate(p, g);
    const double alone = grid.interpolate(p);
    EXPECT_EQ(std::memcmp(&both, &alone, sizeof(double)), 0) << n << ": " << both << " vs " << alone;
    EXPECT_EQ(grid.gradient(p), g);
  }
}

TEST(SdfGrid, ReproducesNodeValuesAtNodes) {
  const SdfGrid grid = makeTrilinearGrid({3, 3, 3}, Vec3::Zero(), 1.0);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) EXPECT_EQ(grid.interpolate(Vec3(i, j, k)), grid.value(i, j, k));
}

TEST(SdfGrid, ClampsQueriesOutsideTheBox) {
  const SdfGrid grid = makeTrilinearGrid({3, 3, 3}, Vec3::Zero(), 1.0);
  EXPECT_FALSE(grid.contains(Vec3(-0.1, 1.0, 1.0)));
  EXPECT_TRUE(grid.contains(Vec3(2.0, 2.0, 2.0)));
  EXPECT_DOUBLE_EQ(grid.interpolate(Vec3(-5.0, 1.0, 1.0)), grid.interpolate(Vec3(0.0, 1.0, 1.0)));
}

TEST(SdfGrid, RejectsInconsistentInput) {
  EXPECT_THROW(SdfGrid({2, 2, 2}, Vec3::Zero(), 1.0, std::vector<float>(7, 0.0f)), Error);
  EXPECT_THROW(SdfGrid({1, 2, 2}, Vec3::Zero(), 1.0, std::vector<float>(4, 0.0f)), Error);
  EXPECT_THROW(SdfGrid({2, 2, 2}, Vec3::Zero(), 0.0, std::vector<float>(8, 0.0f)), Error);
  EXPECT_THROW(SdfGrid({2, 2, 2}, Vec3::Zero(), std::nan(""), std::vector<float>(8, 0.0f)), Error);
  std::vector<float> bad(8, 0.0f);
  bad[3] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(SdfGrid({2, 2, 2}, Vec3::Zero(), 1.0, bad), Error);
}

}  // namespace
}  // namespace sdfccd
