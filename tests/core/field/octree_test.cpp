/// @file
/// @brief MinDistanceOctree: every block's minimum against brute force, odd sizes, and the memory target.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/segment_reference.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/field/min_distance_octree.h"

namespace sdfccd {
namespace {

TEST(MinDistanceOctree, EveryBlockHoldsTheMinimumOfItsNodes) {
  const auto grid = test::randomGrid({14, 7, 22}, Vec3(0.5, -1.0, 2.0), 0.1, 17);
  const MinDistanceOctree octree(*grid);
  const Vec3i cells = grid->cellCounts();
  ASSERT_GE(octree.topLevel(), 1);
  EXPECT_EQ(octree.blockCounts(octree.topLevel()), Vec3i(1, 1, 1));
  EXPECT_EQ(octree.rootMin(), grid->minValue());
  for (int level = 1; level <= octree.topLevel(); ++level) {
    const Vec3i n = octree.blockCounts(level);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(n[a], (cells[a] + (1 << level) - 1) >> level);
    for (int bz = 0; bz < n.z(); ++bz)
      for (int by = 0; by < n.y(); ++by)
        for (int bx = 0; bx < n.x(); ++bx) {
          float m = INFINITY;
          const int s = 1 << level;
          for (int k = bz * s; k <= std::min((bz + 1) * s, cells.z()); ++k)
            for (int j = by * s; j <= std::min((by + 1) * s, cells.y()); ++j)
              for (int i = bx * s; i <= std::min((bx + 1) * s, cells.x()); ++i) m = std::min(m, grid->value(i, j, k));
          ASSERT_EQ(octree.blockMin(level, Vec3i(bx, by, bz)), m) << "level " << level;
        }
  }
}

TEST(MinDistanceOctree, SingleCellGrid) {
  const auto grid = test::randomGrid({2, 2, 2}, Vec3::Zero(), 1.0, 3);
  const MinDistanceOctree octree(*grid);
  EXPECT_EQ(octree.topLevel(), 1);
  EXPECT_EQ(octree.rootMin(), grid->minValue());
}

TEST(MinDistanceOctree, MemoryIsAtMostFifteenPercentOfTheField) {
  for (int n : {17, 33, 64, 65}) {
    const auto grid = test::randomGrid({n, n, n}, Vec3::Zero(), 1.0, 5);
    const GridField field(grid);
    const double ratio = static_cast<double>(field.octree().memoryBytes()) / static_cast<double>(grid->memoryBytes());
    EXPECT_LE(ratio, 0.15) << n;
    EXPECT_EQ(field.memoryBytes(), grid->memoryBytes() + field.octree().memoryBytes());
  }
}

}  // namespace
}  // namespace sdfccd
