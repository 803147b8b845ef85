/// @file
/// @brief cellGradientBoundSquared: a bound on the gradient of a grid's trilinear interpolant inside one cell
/// (paper Section 3.3: the culling radius assumes a Lipschitz bound of the field).
///
/// @details Inside a cell each partial derivative of the trilinear interpolant is a bilinear blend of the 4
/// edge differences along its axis, so it is bounded by the largest of them; the gradient norm is bounded by
/// the norm of the three. Shared by computeCullingBounds (the whole grid's bound, field_culling_bounds.h) and
/// the haptics module's per-block bounds (LocalLipschitzBounds).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "sdfccd/field/sdf_grid.h"

namespace sdfccd {

/// Squared bound on |grad phi| inside cell (i, j, k) (its low corner node), in (value units per cell)^2;
/// sqrt of it / spacing bounds |grad phi| in value units per model unit. Requires 0 <= i, j, k < cellCounts().
/// Inline: it is the inner loop of two O(cells) passes.
inline double cellGradientBoundSquared(const SdfGrid& grid, int i, int j, int k) {
  const std::vector<float>& v = grid.values();
  const std::size_t sy = static_cast<std::size_t>(grid.nodeCounts().x());
  const std::size_t sz = sy * static_cast<std::size_t>(grid.nodeCounts().y());
  const std::size_t base = grid.index(i, j, k);
  const double c[8] = {v[base],      v[base + 1],      v[base + sy],      v[base + 1 + sy],
                       v[base + sz], v[base + 1 + sz], v[base + sy + sz], v[base + 1 + sy + sz]};
  const double gx = std::max(std::max(std::abs(c[1] - c[0]), std::abs(c[3] - c[2])),
                             std::max(std::abs(c[5] - c[4]), std::abs(c[7] - c[6])));
  const double gy = std::max(std::max(std::abs(c[2] - c[0]), std::abs(c[3] - c[1])),
                             std::max(std::abs(c[6] - c[4]), std::abs(c[7] - c[5])));
  const double gz = std::max(std::max(std::abs(c[4] - c[0]), std::abs(c[5] - c[1])),
                             std::max(std::abs(c[6] - c[2]), std::abs(c[7] - c[3])));
  return gx * gx + gy * gy + gz * gz;
}

}  // namespace sdfccd
