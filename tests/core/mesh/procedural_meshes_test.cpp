/// @file
/// @brief Procedural meshes are closed, consistently oriented, outward, and have the right size.
#include "sdfccd/mesh/procedural_meshes.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/shell_test_util.h"
#include "sdfccd/error.h"

namespace sdfccd {
namespace {

TEST(ProceduralMeshes, BoxIsClosedOutwardWithExactVolume) {
  const TriangleMesh box = makeBox(Vec3(1.0, 2.0, 0.5));
  EXPECT_EQ(box.triangles.size(), 12u);
  EXPECT_TRUE(test::closedAndOriented(box));
  EXPECT_NEAR(test::volume(box), 8.0, 1e-12);
  EXPECT_NEAR(test::area(box), 2.0 * (2 * 4 + 2 * 1 + 4 * 1), 1e-12);
  EXPECT_THROW(makeBox(Vec3(1.0, 0.0, 1.0)), Error);
}

TEST(ProceduralMeshes, IcosphereIsClosedOutwardOnTheSphere) {
  const TriangleMesh sphere = makeIcosphere(2.0, 3);
  EXPECT_EQ(sphere.triangles.size(), 20u * 64u);
  EXPECT_TRUE(test::closedAndOriented(sphere));
  for (const auto& v : sphere.vertices) EXPECT_NEAR(v.norm(), 2.0, 1e-12);
  const double exact = 4.0 / 3.0 * kPi * 8.0;
  EXPECT_GT(test::volume(sphere), 0.95 * exact);
  EXPECT_LT(test::volume(sphere), exact);
  EXPECT_THROW(makeIcosphere(-1.0), Error);
}

TEST(ProceduralMeshes, CylinderIsClosedOutward) {
  const TriangleMesh cylinder = makeCylinder(0.5, 2.0, 48);
  EXPECT_TRUE(test::closedAndOriented(cylinder));
  const double exact = kPi * 0.25 * 2.0;
  EXPECT_GT(test::volume(cylinder), 0.99 * exact);
  EXPECT_LT(test::volume(cylinder), exact);
  EXPECT_NEAR(cylinder.bounds().max().y(), 1.0, 1e-15);
  EXPECT_THROW(makeCylinder(1.0, 1.0, 2), Error);
}

TEST(ProceduralMeshes, LathedBowlIsClosedOutwardAndHollow) {
  LathedBowlSettings settings;
  const TriangleMesh bowl = makeLathedBowl(settings);
  EXPECT_TRUE(test::closedAndOriented(bowl));
  const double v = test::volume(bowl);
  EXPECT_GT(v, 0.0);
  // Thin walled: much less than the solid of revolution of its outline.
  EXPECT_LT(v, 0.3 * kPi * settings.rimRadius * settings.rimRadius * settings.height);
  const Box3 box = bowl.bounds();
  EXPECT_NEAR(box.min().y(), -0.5 * settings.height, 1e-12);
  EXPECT_NEAR(box.max().y(), 0.5 * settings.height, 1e-12);
  EXPECT_NEAR(box.max().x(), settings.rimRadius, 1e-12);
  // The centre of the inside of the bowl is empty (above the bottom, below the rim).
  EXPECT_GT(test::meshDistance(bowl, Vec3(0.0, 0.1, 0.0)), 0.1);
  LathedBowlSettings bad;
  bad.wall = 0.5;
  EXPECT_THROW(makeLathedBowl(bad), Error);
}

}  // namespace
}  // namespace sdfccd
