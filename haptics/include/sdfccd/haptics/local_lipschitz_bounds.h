/// @file
/// @brief LocalLipschitzBounds: gradient bounds of a grid field's trilinear interpolant per block of cells, for the
/// god-object's clearance cache (god_object.h; paper Section 4.2, CCD of the shell each simulation cycle).
///
/// @details field_culling_bounds.h gives one bound L for the whole grid: the largest gradient norm of the
/// interpolant over all cells (per cell, each partial derivative is bounded by its largest edge difference along
/// that axis). One steep cell (a box corner of a CSG field reaches sqrt(3)) then slows down every point of the
/// shell, although near a smooth wall the interpolant's gradient is about 1. Here the grid is cut into blocks of
/// `blockCells`^3 cells; each block stores the largest per-cell bound over itself and its 26 neighbours. A point
/// p inside the box lies at least blockCells cells from the outside of its block's neighbourhood, so for every q
/// with |q - p| <= reach() (= blockCells * spacing), the straight path from p to q stays in that neighbourhood
/// (and in the box, both convex) and phi(q) >= phi(p) - lipschitzNear(p) * |q - p|.
/// Built once per god-object (one pass over the cells); read-only afterwards.
#pragma once

#include <vector>

#include "sdfccd/field/sdf_grid.h"
#include "sdfccd/math_types.h"

namespace sdfccd::haptics {

class LocalLipschitzBounds {
 public:
  LocalLipschitzBounds() = default;
  /// One pass over the cells. Throws sdfccd::Error on blockCells < 1 or an empty grid.
  explicit LocalLipschitzBounds(const SdfGrid& grid, int blockCells = 8);

  bool empty() const { return m_bounds.empty(); }
  /// A bound on |grad phi| over the ball of radius reach() around `pointInSdf` (which must be in the grid's box;
  /// outside, the nearest block is used, which is not a bound there). 1/model units * model units: unitless.
  double lipschitzNear(const Vec3& pointInSdf) const;
  /// Model units: blockCells * spacing.
  double reach() const { return m_reach; }

 private:
  Vec3i m_blocks = Vec3i::Zero();
  Vec3 m_origin = Vec3::Zero();
  double m_blockSize = 0.0;  // model units
  double m_reach = 0.0;
  std::vector<float> m_bounds;  // per block, rounded up, over the block and its neighbours
};

}  // namespace sdfccd::haptics
