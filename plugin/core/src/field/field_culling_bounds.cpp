/// @file
/// @brief Lipschitz and boundary bounds of grid fields for the point tree's culling (see field_culling_bounds.h).
#include "sdfccd/field/field_culling_bounds.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "sdfccd/field/cell_gradient_bound.h"

namespace sdfccd {

FieldCullingBounds computeCullingBounds(const SdfGrid& grid) {
  FieldCullingBounds bounds;
  bounds.bounded = true;
  bounds.box = grid.box();
  const Vec3i n = grid.nodeCounts();
  // Lowest value on the box faces: the trilinear interpolant on a face blends face nodes only.
  double boundaryMin = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n.z(); ++k) {
    for (int j = 0; j < n.y(); ++j) {
      const bool faceJK = k == 0 || k == n.z() - 1 || j == 0 || j == n.y() - 1;
      for (int i = 0; i < n.x(); i += (faceJK ? 1 : std::max(1, n.x() - 1))) {
        boundaryMin = std::min(boundaryMin, static_cast<double>(grid.value(i, j, k)));
      }
    }
  }
  bounds.boundaryMin = boundaryMin;
  // Largest gradient norm of the trilinear interpolant over all cells.
  const Vec3i cells = grid.cellCounts();
  double worstSq = 0.0;
  for (int k = 0; k < cells.z(); ++k) {
    for (int j = 0; j < cells.y(); ++j) {
      for (int i = 0; i < cells.x(); ++i) worstSq = std::max(worstSq, cellGradientBoundSquared(grid, i, j, k));
    }
  }
  // A hair of slack for the rounding of the interpolation itself.
  bounds.lipschitz = std::sqrt(worstSq) / grid.spacing() * (1.0 + 1e-9);
  return bounds;
}

FieldCullingBounds fieldCullingBounds(const GridField& field) {
  struct Entry {
    std::weak_ptr<const SdfGrid> grid;
    const SdfGrid* key;
    FieldCullingBounds bounds;
  };
  static std::mutex mutex;
  static std::vector<Entry> cache;
  const std::shared_ptr<const SdfGrid>& grid = field.gridPtr();
  {
    std::lock_guard<std::mutex> lock(mutex);
    cache.erase(std::remove_if(cache.begin(), cache.end(), [](const Entry& e) { return e.grid.expired(); }),
                cache.end());
    for (const auto& e : cache) {
      if (e.key == grid.get()) return e.bounds;
    }
  }
  const FieldCullingBounds bounds = computeCullingBounds(*grid);
  std::lock_guard<std::mutex> lock(mutex);
  cache.push_back({grid, grid.get(), bounds});
  return bounds;
}

}  // namespace sdfccd
