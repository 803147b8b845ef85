/// @file
/// @brief Lipschitz and boundary bounds of grid fields for the point tree's culling (see field_culling_bounds.h).
#include "sdfccd/field_culling_bounds.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

namespace sdfccd {

FieldCullingBounds computeCullingBounds(const SdfGrid& grid) {
  FieldCullingBounds bounds;
  bounds.bounded = true;
  bounds.box = grid.box();
  const Vec3i n = grid.nodeCounts();
  const auto& v = grid.values();
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
  // Largest gradient norm of the trilinear interpolant: per cell, each partial derivative is bounded by its
  // largest edge difference along that axis.
  const std::size_t sx = 1;
  const std::size_t sy = static_cast<std::size_t>(n.x());
  const std::size_t sz = sy * static_cast<std::size_t>(n.y());
  double worstSq = 0.0;
  for (int k = 0; k + 1 < n.z(); ++k) {
    for (int j = 0; j + 1 < n.y(); ++j) {
      for (int i = 0; i + 1 < n.x(); ++i) {
        const std::size_t base = grid.index(i, j, k);
        const double c[8] = {v[base],      v[base + sx],      v[base + sy],      v[base + sx + sy],
                             v[base + sz], v[base + sx + sz], v[base + sy + sz], v[base + sx + sy + sz]};
        const double gx = std::max(std::max(std::abs(c[1] - c[0]), std::abs(c[3] - c[2])),
                                   std::max(std::abs(c[5] - c[4]), std::abs(c[7] - c[6])));
        const double gy = std::max(std::max(std::abs(c[2] - c[0]), std::abs(c[3] - c[1])),
                                   std::max(std::abs(c[6] - c[4]), std::abs(c[7] - c[5])));
        const double gz = std::max(std::max(std::abs(c[4] - c[0]), std::abs(c[5] - c[1])),
                                   std::max(std::abs(c[6] - c[2]), std::abs(c[7] - c[3])));
        worstSq = std::max(worstSq, gx * gx + gy * gy + gz * gz);
      }
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
