/// @file
/// @brief A signed distance field sampled on a uniform grid of cubic cells, with trilinear interpolation.
///
/// @details Node (i, j, k) sits at origin + (i, j, k) * spacing (the SDFGen convention), i fastest in memory.
/// Values are stored as float (half the memory of double); all arithmetic on them is done in double.
/// Values are negative inside the object. The field is immutable once built, so any number of threads may
/// read it at once.
///
/// Outside-the-box policy: the field is defined only inside its box. interpolate() and gradient() clamp the
/// query to the box (they never read out of bounds); callers that must distinguish "outside" use contains().
/// The segment CCD treats the part of a segment outside the box as free of contact.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "sdfccd/field/trilinear.h"
#include "sdfccd/math_types.h"

namespace sdfccd {

class SdfGrid {
 public:
  SdfGrid() = default;
  /// Takes ownership of `values` (nodeCounts.prod() of them, i fastest). Throws sdfccd::Error on
  /// inconsistent sizes, fewer than 2 nodes along an axis, non-finite or non-positive spacing, non-finite
  /// origin or values.
  SdfGrid(const Vec3i& nodeCounts, const Vec3& origin, double spacing, std::vector<float> values);

  const Vec3i& nodeCounts() const { return m_nodeCounts; }
  Vec3i cellCounts() const { return m_nodeCounts.array() - 1; }
  const Vec3& origin() const { return m_origin; }  ///< position of node (0,0,0), field frame (model units)
  double spacing() const { return m_spacing; }     ///< edge length of a cell (model units)
  /// The box spanned by the nodes, in the field's frame.
  Box3 box() const { return Box3(m_origin, m_boxMax); }
  bool empty() const { return m_values.empty(); }

  /// Linear index of node (i, j, k).
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(m_nodeCounts.x()) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(m_nodeCounts.y()) * static_cast<std::size_t>(k));
  }
  float value(int i, int j, int k) const { return m_values[index(i, j, k)]; }
  const std::vector<float>& values() const { return m_values; }
  /// Smallest and largest value.
  float minValue() const { return m_minValue; }
  float maxValue() const { return m_maxValue; }
  /// Bytes held by the values.
  std::size_t memoryBytes() const { return m_values.size() * sizeof(float); }

  // The point queries below are defined inline (after the class): every CCD node test, certificate and penalty
  // sample runs them, and a call per step of each would cost more than its arithmetic.

  /// True when `pointInSdf` lies in the closed box of the field.
  bool contains(const Vec3& pointInSdf) const;
  /// The cell containing `pointInSdf` (clamped to the grid) and the local coordinates in [0,1]^3 within it.
  void locate(const Vec3& pointInSdf, Vec3i& outCell, Vec3& outLocal) const;
  /// The eight corner values of cell c, in the order (x fastest): 000, 100, 010, 110, 001, 101, 011, 111.
  void cellCorners(const Vec3i& cell, double outCorners[8]) const;
  /// Trilinear interpolation (clamped to the box). Model units. The same value as the two-output form, without
  /// its gradient.
  double interpolate(const Vec3& pointInSdf) const;
  /// Gradient of the trilinear interpolant (clamped to the box). Not normalized.
  Vec3 gradient(const Vec3& pointInSdf) const;
  /// Both at once.
  double interpolate(const Vec3& pointInSdf, Vec3& outGradient) const;

 private:
  Vec3i m_nodeCounts = Vec3i::Zero();
  Vec3 m_origin = Vec3::Zero();
  double m_spacing = 0.0;
  Vec3 m_boxMax = Vec3::Zero();  // origin + spacing * cellCounts (box(), contains()), computed once
  std::vector<float> m_values;
  float m_minValue = 0.0f;
  float m_maxValue = 0.0f;
};

inline bool SdfGrid::contains(const Vec3& pointInSdf) const {
  return (pointInSdf.array() >= m_origin.array()).all() && (pointInSdf.array() <= m_boxMax.array()).all();
}

inline void SdfGrid::locate(const Vec3& pointInSdf, Vec3i& outCell, Vec3& outLocal) const {
  const Vec3 u = (pointInSdf - m_origin) / m_spacing;
  for (int a = 0; a < 3; ++a) {
    const int last = m_nodeCounts[a] - 2;
    double f = std::floor(u[a]);
    // NaN compares false both ways and lands in cell 0 with local 0: callers validate inputs first.
    int c = f < 0.0 ? 0 : (f > last ? last : static_cast<int>(f));
    outCell[a] = c;
    outLocal[a] = std::clamp(u[a] - c, 0.0, 1.0);
  }
}

inline void SdfGrid::cellCorners(const Vec3i& cell, double outCorners[8]) const {
  const std::size_t base = index(cell.x(), cell.y(), cell.z());
  const std::size_t dy = static_cast<std::size_t>(m_nodeCounts.x());
  const std::size_t dz = dy * static_cast<std::size_t>(m_nodeCounts.y());
  const float* v = m_values.data() + base;
  outCorners[0] = v[0];
  outCorners[1] = v[1];
  outCorners[2] = v[dy];
  outCorners[3] = v[dy + 1];
  outCorners[4] = v[dz];
  outCorners[5] = v[dz + 1];
  outCorners[6] = v[dz + dy];
  outCorners[7] = v[dz + dy + 1];
}

inline double SdfGrid::interpolate(const Vec3& pointInSdf) const {
  Vec3i cell;
  Vec3 w;
  locate(pointInSdf, cell, w);
  double c[8];
  cellCorners(cell, c);
  return trilinear(c, w);  // the same operations as the two-output form's value
}

inline Vec3 SdfGrid::gradient(const Vec3& pointInSdf) const {
  Vec3 g;
  interpolate(pointInSdf, g);
  return g;
}

inline double SdfGrid::interpolate(const Vec3& pointInSdf, Vec3& outGradient) const {
  Vec3i cell;
  Vec3 w;
  locate(pointInSdf, cell, w);
  double c[8];
  cellCorners(cell, c);
  const double x = w.x(), y = w.y(), z = w.z();
  // Interpolate along x, then y, then z; the gradient follows from the same partial sums.
  const TrilinearSums s = trilinearSums(c, x, y);
  const double c00 = s.c00, c10 = s.c10, c01 = s.c01, c11 = s.c11, c0 = s.c0, c1 = s.c1;
  const double dx0 = (c[1] - c[0]) + y * ((c[3] - c[2]) - (c[1] - c[0]));
  const double dx1 = (c[5] - c[4]) + y * ((c[7] - c[6]) - (c[5] - c[4]));
  outGradient.x() = (dx0 + z * (dx1 - dx0)) / m_spacing;
  outGradient.y() = ((c10 - c00) + z * ((c11 - c01) - (c10 - c00))) / m_spacing;
  outGradient.z() = (c1 - c0) / m_spacing;
  return c0 + z * (c1 - c0);
}

}  // namespace sdfccd
