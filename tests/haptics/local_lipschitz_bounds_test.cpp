/// @file
/// @brief LocalLipschitzBounds: a true bound within its reach (random pairs on the peg's CSG grid, brute force
/// against the interpolant), never above the global bound, and about 1 near a smooth wall where the global bound
/// is sqrt(3).
#include "sdfccd/haptics/local_lipschitz_bounds.h"

#include <gtest/gtest.h>

#include <random>

#include "sdfccd/error.h"
#include "sdfccd/field/field_culling_bounds.h"
#include "sdfccd/haptics/haptic_scene.h"

namespace sdfccd::haptics {
namespace {

TEST(LocalLipschitzBounds, BoundsThePhiChangeWithinItsReach) {
  const HapticScene scene = loadHapticScene(std::string(SDFCCD_ASSETS_DIR) + "/scenes/haptics/peg-in-hole.json");
  const SdfGrid& grid = scene.grid->grid();
  const LocalLipschitzBounds local(grid, 4);
  const FieldCullingBounds global = computeCullingBounds(grid);
  EXPECT_NEAR(local.reach(), 4.0 * grid.spacing(), 1e-5 * grid.spacing());
  const Box3 box = grid.box();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int tested = 0;
  for (int n = 0; n < 20000; ++n) {
    const Vec3 p = box.min() + box.sizes().cwiseProduct(Vec3(unit(rng), unit(rng), unit(rng)));
    const Vec3 dir = Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5).normalized();
    const Vec3 q = p + unit(rng) * local.reach() * dir;
    if (!box.contains(q)) continue;
    const double l = local.lipschitzNear(p);
    EXPECT_LE(l, global.lipschitz * (1.0 + 1e-6));
    EXPECT_LE(std::abs(grid.interpolate(q) - grid.interpolate(p)), l * (q - p).norm() + 1e-12);
    ++tested;
  }
  EXPECT_GT(tested, 10000);
  // Near the middle of the hole's wall (radius 8.035 mm, centre y = -5 mm): the field is the distance to a
  // cylinder, whose interpolant is nearly 1-Lipschitz; the global bound sees the box corners.
  EXPECT_NEAR(global.lipschitz, std::sqrt(3.0), 1e-3);
  EXPECT_LT(local.lipschitzNear(Vec3(0.008, -0.012, 0.0)), 1.1);
  EXPECT_THROW(LocalLipschitzBounds(grid, 0), Error);
}

}  // namespace
}  // namespace sdfccd::haptics
