/// @file
/// @brief cellAxisBounds and cellGradientBoundSquared: bounds on the gradient of a grid's trilinear interpolant inside
/// one cell (paper Section 3.3: the culling radius assumes a Lipschitz bound of the field).
///
/// @details Inside a cell each partial derivative of the trilinear interpolant is a bilinear blend of the 4
/// edge differences along its axis, so it is bounded by the largest of them; the gradient norm is bounded by
/// the norm of the three. Shared by computeCullingBounds (the whole grid's bound, field_culling_bounds.h) and
/// the haptics module's per-block bounds (LocalLipschitzBounds); the per-axis bounds by AxisLipschitzBounds.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "sdfccd/field/sdf_grid.h"

namespace sdfccd {

/// Per axis, the largest edge difference of cell (i, j, k) (its low corner node) along that axis, in value units
/// per cell: a bound on |d phi / d axis| inside the cell (trilinear: each partial derivative is an interpolation of
/// its edges' differences). Requires 0 <= i, j, k < cellCounts(). Inline: the inner loop of O(cells) passes.
inline std::array<double, 3> cellAxisBounds(const SdfGrid& grid, int i, int j, int k) {
  const std::vector<float>& v = grid.values();
  const std::size_t sy = static_cast<std::size_t>(grid.nodeCounts().x());
  const std::size_t sz = sy * static_cast<std::size_t>(grid.nodeCounts().y());
  const std::size_t base = grid.index(i, j, k);
  const double c[8] = {v[base],      v[base + 1],      v[base + sy],      v[base + 1 + sy],
                       v[base + sz], v[base + 1 + sz], v[base + sy + sz], v[base + 1 + sy + sz]};
  const auto edge = [&](int a, int b) { return std::abs(c[b] - c[a]); };
  return {std::max(std::max(edge(0, 1), edge(2, 3)), std::max(edge(4, 5), edge(6, 7))),
          std::max(std::max(edge(0, 2), edge(1, 3)), std::max(edge(4, 6), edge(5, 7))),
          std::max(std::max(edge(0, 4), edge(1, 5)), std::max(edge(2, 6), edge(3, 7)))};
}

/// Squared bound on |grad phi| inside cell (i, j, k) (its low corner node), in (value units per cell)^2;
/// sqrt of it / spacing bounds |grad phi| in value units per model unit. Requires 0 <= i, j, k < cellCounts().
inline double cellGradientBoundSquared(const SdfGrid& grid, int i, int j, int k) {
  const std::array<double, 3> g = cellAxisBounds(grid, i, j, k);
  return g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
}

}  // namespace sdfccd
