/// @file
/// @brief MinDistanceOctree: the minimum field value over blocks of cells, for skipping cells (Section 3.2).
///
/// @details The paper stores phi_min in every octree node down to single cells and so takes about twice the
/// field's memory (Table 1). Here the octree is a min-pyramid over blocks of 2^L x 2^L x 2^L cells for levels
/// L = 1 .. topLevel(); the cell level (L = 0) is not stored because a cell's minimum is the minimum of its
/// eight corners, which the walk reads anyway. Level L has ceil(cells / 2^L) blocks per axis (blocks at the
/// far faces are partial). With one float per block the pyramid costs 1/8 + 1/64 + ... < 1/7 of one float
/// per cell, i.e. at most ~14.3% of the grid's memory (the grid has more nodes than cells).
///
/// Block (bx, by, bz) of level L covers cells [bx 2^L, (bx+1) 2^L) x ... (clamped to the grid) and stores the
/// minimum over the grid nodes of those cells, so phi >= blockMin everywhere inside the block's box
/// (trilinear interpolation is a convex combination of the corners).
///
/// Built bottom-up (level 1 from the nodes, level L+1 from level L) when a GridField is made; never stored on
/// disk. Immutable after construction: any number of threads may read it.
#pragma once

#include <cstddef>
#include <vector>

#include "sdfccd/math_types.h"

namespace sdfccd {

class SdfGrid;

class MinDistanceOctree {
 public:
  MinDistanceOctree() = default;
  /// Builds the pyramid over `grid` (uses up to all cores for the first level).
  explicit MinDistanceOctree(const SdfGrid& grid);

  /// Bytes held by the octree.
  std::size_t memoryBytes() const { return m_values.size() * sizeof(float); }
  /// Coarsest level: one block covers the whole grid. 0 for an empty octree.
  int topLevel() const { return static_cast<int>(m_levelOffsets.size()); }
  /// Blocks per axis at `level` (1 .. topLevel()).
  const Vec3i& blockCounts(int level) const { return m_levelCounts[static_cast<std::size_t>(level - 1)]; }
  /// Minimum over block `block` of `level` (1 .. topLevel()). No bounds check in release builds.
  float blockMin(int level, const Vec3i& block) const {
    const Vec3i& n = m_levelCounts[static_cast<std::size_t>(level - 1)];
    return m_values[m_levelOffsets[static_cast<std::size_t>(level - 1)] + static_cast<std::size_t>(block.x()) +
                    static_cast<std::size_t>(n.x()) *
                        (static_cast<std::size_t>(block.y()) +
                         static_cast<std::size_t>(n.y()) * static_cast<std::size_t>(block.z()))];
  }
  /// Minimum over the block of `level` that contains `cell` (cell coordinates).
  float blockMinAtCell(int level, const Vec3i& cell) const {
    return blockMin(level, Vec3i(cell.x() >> level, cell.y() >> level, cell.z() >> level));
  }
  /// Minimum of the whole field (the root).
  float rootMin() const { return m_values.empty() ? 0.0f : m_values.back(); }

 private:
  std::vector<float> m_values;              ///< all levels, finest (L = 1) first; the root is last
  std::vector<std::size_t> m_levelOffsets;  ///< start of level L at [L - 1]
  std::vector<Vec3i> m_levelCounts;         ///< blocks per axis of level L at [L - 1]
};

}  // namespace sdfccd
