/// @file
/// @brief The Lipschitz and boundary bounds of a grid for the point tree's culling (see field_culling_bounds.h).
#include "sdfccd/field/field_culling_bounds.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sdfccd/field/cell_gradient_bound.h"
#include "sdfccd/tolerances.h"

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
  bounds.lipschitz = std::sqrt(worstSq) / grid.spacing() * tolerance::kBoundGrowth;
  return bounds;
}

}  // namespace sdfccd
