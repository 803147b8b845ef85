/// @file
/// @brief MinDistanceOctree: bottom-up construction of the min-pyramid (paper Section 3.2).
#include "sdfccd/field/min_distance_octree.h"

#include <algorithm>

#include "sdfccd/field/sdf_grid.h"
#include "sdfccd/parallel_for.h"

namespace sdfccd {

MinDistanceOctree::MinDistanceOctree(const SdfGrid& grid) {
  if (grid.empty()) return;
  const Vec3i cells = grid.cellCounts();
  // Level sizes: ceil(cells / 2^L) until one block covers everything.
  std::size_t total = 0;
  for (int level = 1;; ++level) {
    Vec3i n;
    for (int a = 0; a < 3; ++a) n[a] = (cells[a] + (1 << level) - 1) >> level;
    m_levelOffsets.push_back(total);
    m_levelCounts.push_back(n);
    total += static_cast<std::size_t>(n.x()) * static_cast<std::size_t>(n.y()) * static_cast<std::size_t>(n.z());
    if ((n.array() == 1).all()) break;
  }
  m_values.assign(total, 0.0f);

  // Level 1: block b covers cells [2b, 2b+2), i.e. nodes [2b, 2b+2] clamped to the grid.
  const Vec3i nodes = grid.nodeCounts();
  const Vec3i& n1 = m_levelCounts[0];
  float* level1 = m_values.data();
  parallelFor(static_cast<std::size_t>(n1.z()), 0, [&](std::size_t bz, int) {
    const int k0 = 2 * static_cast<int>(bz), k1 = std::min(k0 + 2, nodes.z() - 1);
    for (int by = 0; by < n1.y(); ++by) {
      const int j0 = 2 * by, j1 = std::min(j0 + 2, nodes.y() - 1);
      for (int bx = 0; bx < n1.x(); ++bx) {
        const int i0 = 2 * bx, i1 = std::min(i0 + 2, nodes.x() - 1);
        float m = grid.value(i0, j0, k0);
        for (int k = k0; k <= k1; ++k)
          for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) m = std::min(m, grid.value(i, j, k));
        level1[static_cast<std::size_t>(bx) +
               static_cast<std::size_t>(n1.x()) *
                   (static_cast<std::size_t>(by) + static_cast<std::size_t>(n1.y()) * bz)] = m;
      }
    }
  });

  // Level L+1 from level L: the minimum of up to 8 children.
  for (std::size_t level = 1; level < m_levelCounts.size(); ++level) {
    const Vec3i& nc = m_levelCounts[level - 1];
    const Vec3i& np = m_levelCounts[level];
    const float* child = m_values.data() + m_levelOffsets[level - 1];
    float* parent = m_values.data() + m_levelOffsets[level];
    for (int bz = 0; bz < np.z(); ++bz)
      for (int by = 0; by < np.y(); ++by)
        for (int bx = 0; bx < np.x(); ++bx) {
          float m = child[static_cast<std::size_t>(2 * bx) +
                          static_cast<std::size_t>(nc.x()) *
                              (static_cast<std::size_t>(2 * by) + static_cast<std::size_t>(nc.y()) * (2 * bz))];
          for (int k = 2 * bz; k < std::min(2 * bz + 2, nc.z()); ++k)
            for (int j = 2 * by; j < std::min(2 * by + 2, nc.y()); ++j)
              for (int i = 2 * bx; i < std::min(2 * bx + 2, nc.x()); ++i)
                m = std::min(m, child[static_cast<std::size_t>(i) +
                                      static_cast<std::size_t>(nc.x()) *
                                          (static_cast<std::size_t>(j) + static_cast<std::size_t>(nc.y()) * k)]);
          parent[static_cast<std::size_t>(bx) +
                 static_cast<std::size_t>(np.x()) *
                     (static_cast<std::size_t>(by) + static_cast<std::size_t>(np.y()) * bz)] = m;
        }
  }
}

}  // namespace sdfccd
