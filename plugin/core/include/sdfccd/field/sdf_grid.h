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

#include <cstddef>
#include <vector>

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
  Box3 box() const { return Box3(m_origin, m_origin + m_spacing * cellCounts().cast<double>()); }
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

  /// True when `pointInSdf` lies in the closed box of the field.
  bool contains(const Vec3& pointInSdf) const;
  /// The cell containing `pointInSdf` (clamped to the grid) and the local coordinates in [0,1]^3 within it.
  void locate(const Vec3& pointInSdf, Vec3i& outCell, Vec3& outLocal) const;
  /// The eight corner values of cell c, in the order (x fastest): 000, 100, 010, 110, 001, 101, 011, 111.
  void cellCorners(const Vec3i& cell, double outCorners[8]) const;
  /// Trilinear interpolation (clamped to the box). Model units.
  double interpolate(const Vec3& pointInSdf) const;
  /// Gradient of the trilinear interpolant (clamped to the box). Not normalized.
  Vec3 gradient(const Vec3& pointInSdf) const;
  /// Both at once.
  double interpolate(const Vec3& pointInSdf, Vec3& outGradient) const;

 private:
  Vec3i m_nodeCounts = Vec3i::Zero();
  Vec3 m_origin = Vec3::Zero();
  double m_spacing = 0.0;
  std::vector<float> m_values;
  float m_minValue = 0.0f;
  float m_maxValue = 0.0f;
};

}  // namespace sdfccd
