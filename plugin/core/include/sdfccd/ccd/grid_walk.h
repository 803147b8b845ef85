/// @file
/// @brief GridWalk: the 3D DDA that visits the cells a segment crosses, in order (paper Section 3.1, [40]).
///
/// @details Works in grid-index coordinates u = (p - origin) / spacing, relative to the grid's origin, so a
/// field far from zero loses no precision. The segment is u(t) = u0 + t d for t in the clipped range
/// [tBegin, tEnd]. Cells are stepped with integers; the t at which the walk leaves a cell along an axis is
/// always computed by the same formula, (boundary - u0[a]) * invD[a], never accumulated, so two walks over
/// the same segment (one of which jumps over octree blocks with jumpTo) see bit-identical cell t-ranges.
///
/// Degenerate segments:
/// - an axis with d[a] == 0 (segment in a grid plane, along a grid line, or of zero length) never steps along
///   that axis; a coordinate exactly on a grid plane picks the cell above it (clamped to the grid), which is
///   harmless because the trilinear field is continuous across cell faces;
/// - through an edge or a vertex, the walk steps one axis at a time and reports zero-length cells
///   (cellEnd() == cellBegin()) in between; callers skip them (their single point belongs to the neighbours);
/// - |d[a]| so small that 1 / d[a] overflows is treated as 0.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "sdfccd/math_types.h"

namespace sdfccd {

class GridWalk {
 public:
  /// Starts at tBegin. `cellCounts` cells per axis (>= 1); [tBegin, tEnd] must lie in the box [0, cellCounts].
  GridWalk(const Vec3& u0, const Vec3& d, const Vec3i& cellCounts, double tBegin, double tEnd)
      : m_u0(u0), m_d(d), m_last(cellCounts.array() - 1), m_tEnd(tEnd) {
    for (int a = 0; a < 3; ++a) {
      m_invD[a] = d[a] != 0.0 ? 1.0 / d[a] : 0.0;
      if (!std::isfinite(m_invD[a])) m_invD[a] = 0.0;
      if (m_invD[a] == 0.0) m_d[a] = 0.0;
      m_step[a] = m_d[a] > 0.0 ? 1 : (m_d[a] < 0.0 ? -1 : 0);
    }
    locate(tBegin);
  }

  const Vec3i& cell() const { return m_cell; }
  double cellBegin() const { return m_tIn; }                           ///< t where the walk entered cell()
  double cellEnd() const { return std::min(nextCrossing(), m_tEnd); }  ///< t where it leaves cell()
  double end() const { return m_tEnd; }
  const Vec3& u0() const { return m_u0; }
  const Vec3& direction() const { return m_d; }  ///< d (0 on axes treated as not moving)

  /// Local coordinates in [0,1]^3 of u(t) within cell() (clamped against rounding).
  Vec3 local(double t) const {
    Vec3 w;
    for (int a = 0; a < 3; ++a) w[a] = std::clamp(m_u0[a] + t * m_d[a] - m_cell[a], 0.0, 1.0);
    return w;
  }

  /// Steps to the next cell; false when the segment ends in the current one.
  bool next() {
    int axis = 0;
    if (m_tMax[1] < m_tMax[axis]) axis = 1;
    if (m_tMax[2] < m_tMax[axis]) axis = 2;
    const double t = m_tMax[axis];
    if (!(t < m_tEnd)) return false;
    const int c = m_cell[axis] + m_step[axis];
    if (c < 0 || c > m_last[axis]) return false;  // left the box by rounding: the rest is a sliver
    m_cell[axis] = c;
    m_tIn = t;
    m_tMax[axis] = exitTime(axis, c);
    return true;
  }

  /// t at which the segment leaves the box of cells [lo, hi] (inclusive cell indices) along any axis.
  double exitTimeOfBlock(const Vec3i& lo, const Vec3i& hi) const {
    double t = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      if (m_step[a] > 0) t = std::min(t, exitTime(a, hi[a]));
      if (m_step[a] < 0) t = std::min(t, exitTime(a, lo[a]));
    }
    return t;
  }

  /// Restarts the walk at time t (>= the current cellBegin(), < end()), e.g. after skipping an octree block.
  void jumpTo(double t) { locate(t); }

 private:
  double nextCrossing() const { return std::min(m_tMax[0], std::min(m_tMax[1], m_tMax[2])); }
  /// t at which the segment leaves cell index c along axis a (infinite when it does not move along a).
  double exitTime(int a, int c) const {
    if (m_step[a] > 0) return (static_cast<double>(c + 1) - m_u0[a]) * m_invD[a];
    if (m_step[a] < 0) return (static_cast<double>(c) - m_u0[a]) * m_invD[a];
    return std::numeric_limits<double>::infinity();
  }
  /// t at which the segment enters cell index c along axis a (-inf when it does not move along a).
  double entryTime(int a, int c) const {
    if (m_step[a] > 0) return (static_cast<double>(c) - m_u0[a]) * m_invD[a];
    if (m_step[a] < 0) return (static_cast<double>(c + 1) - m_u0[a]) * m_invD[a];
    return -std::numeric_limits<double>::infinity();
  }
  /// The cell holding (t, t + dt) for small dt > 0, decided by the same exit/entry formulas as the stepping.
  void locate(double t) {
    for (int a = 0; a < 3; ++a) {
      const double u = m_u0[a] + t * m_d[a];
      int c;
      if (m_step[a] >= 0) {
        c = static_cast<int>(std::clamp(std::floor(u), 0.0, static_cast<double>(m_last[a])));
      } else {
        c = static_cast<int>(std::clamp(std::ceil(u) - 1.0, 0.0, static_cast<double>(m_last[a])));
      }
      if (m_step[a] != 0) {
        // Agree with the stepping formulas: entry(c) <= t < exit(c), as far as the grid allows.
        const int toward = m_step[a];
        while (entryTime(a, c) > t && c - toward >= 0 && c - toward <= m_last[a]) c -= toward;
        while (exitTime(a, c) <= t && c + toward >= 0 && c + toward <= m_last[a]) c += toward;
      }
      m_cell[a] = c;
      m_tMax[a] = exitTime(a, c);
    }
    m_tIn = t;
  }

  Vec3 m_u0;
  Vec3 m_d;
  Vec3 m_invD;
  Vec3i m_last;
  Vec3i m_step;
  Vec3i m_cell;
  Vec3 m_tMax;
  double m_tIn = 0.0;
  double m_tEnd = 0.0;
};

}  // namespace sdfccd
