/// @file
/// @brief AxisLipschitzBounds: per-axis gradient bounds of a grid field's trilinear interpolant per block of cells,
/// for certificates that split a motion along and across a wall (the coherent every-contact query,
/// rigid_ccd_coherence.h, and the god-object's clearance cache; paper Sections 3.3 and 4).
///
/// @details A single Lipschitz bound L charges every direction of motion the same: a peg sliding 15 um per tick
/// along a wall 50 um away uses up a point's clearance in a few ticks although phi hardly changes along the wall.
/// Inside one cell each partial derivative of the trilinear interpolant is a bilinear blend of its 4 edge
/// differences along that axis (cell_gradient_bound.h), so |d phi / d x_a| <= G_a (the largest of them / spacing)
/// holds in the whole closed cell, one-sided on its faces, where the gradient itself jumps. phi is continuous, so
/// along any straight path q -> q + d that stays in cells with those bounds,
///   |phi(q + d) - phi(q)| <= G_x |d_x| + G_y |d_y| + G_z |d_z|,
/// whatever the gradient does across the cell faces on the way. Deep in a hole with an axis-aligned wall G_y is
/// (near) 0: motion along the wall costs nothing.
///
/// The grid is cut into blocks of `blockCells`^3 cells; each block stores, per axis, the largest per-cell bound
/// over itself and its 26 neighbours (rounded up), and their norm. A point p inside the box lies at least
/// blockCells cells from the outside of its block's neighbourhood, so every straight path from p of length up to
/// reach() (= blockCells * spacing, a hair less) stays in that neighbourhood and the bounds of p's block hold on
/// it (and the box is convex: a path between two points of the box stays in it).
/// Built once per grid (one pass over the cells); read-only afterwards, safe to share between threads.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "sdfccd/field/sdf_grid.h"
#include "sdfccd/math_types.h"

namespace sdfccd {

class GridField;

class AxisLipschitzBounds {
 public:
  /// The bounds of one block (value units per model unit; rounded up).
  struct Block {
    float x = 0.0f;
    float y = 0.0f;
    float z = 0.0f;
    float norm = 0.0f;  ///< >= |(x, y, z)|: bounds |grad phi| in any direction
  };

  /// One pass over the cells. Throws sdfccd::Error on blockCells < 1 or an empty grid.
  AxisLipschitzBounds(const SdfGrid& grid, int blockCells);

  /// The block count is kept near 2^18 at most (a few MB): 2 cells per block for small grids, more for large ones.
  static int defaultBlockCells(const SdfGrid& grid);

  /// The block of `pointInSdf`, or -1 outside the grid's box (the bounds hold only for points in the box).
  int blockOf(const Vec3& pointInSdf) const;
  const Block& block(int index) const { return m_bounds[static_cast<std::size_t>(index)]; }
  /// Model units: how far from a point of a block its bounds hold.
  double reach() const { return m_reach; }
  int blockCells() const { return m_blockCells; }
  /// The grid's box (field frame): every point with a block lies in it.
  const Box3& box() const { return m_box; }

 private:
  Box3 m_box;
  Vec3i m_blocks = Vec3i::Zero();
  Vec3 m_origin = Vec3::Zero();
  double m_blockSize = 0.0;  // model units
  double m_reach = 0.0;
  int m_blockCells = 0;
  std::vector<Block> m_bounds;
};

/// The bounds of `field`'s grid with the default block size, shared by every caller that asks for the same field
/// (keyed by its instance id, kept while a caller holds them; thread safe). The first request builds them.
std::shared_ptr<const AxisLipschitzBounds> sharedAxisLipschitzBounds(const GridField& field);

}  // namespace sdfccd
