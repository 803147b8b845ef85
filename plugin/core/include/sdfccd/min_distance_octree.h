/// @file
/// @brief MinDistanceOctree: the minimum field value over blocks of cells, for skipping cells (Section 3.2).
///
/// @details Built bottom-up from the grid. (Declaration to be completed with the segment CCD.)
#pragma once

#include <cstddef>

namespace sdfccd {

class SdfGrid;

class MinDistanceOctree {
 public:
  MinDistanceOctree() = default;
  explicit MinDistanceOctree(const SdfGrid& grid);
  /// Bytes held by the octree.
  std::size_t memoryBytes() const;
};

}  // namespace sdfccd
