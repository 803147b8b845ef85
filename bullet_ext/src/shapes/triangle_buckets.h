/// @file
/// @brief TriangleBuckets: a uniform grid of buckets over a mesh, each listing the triangles whose box overlaps
/// it (compressed rows: one offsets array, one index array). Private to sdfccd::bullet: SdfccdShape's ray and
/// sweep queries hand Bullet's per-triangle callbacks only the triangles near the part of the query that the
/// distance field says is near the surface.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd::bullet::detail {

class TriangleBuckets {
 public:
  /// Buckets of edge `bucketSize` (> 0) over the mesh's box.
  TriangleBuckets(const TriangleMesh& mesh, double bucketSize);

  /// Appends to `out` the index of every triangle listed in a bucket overlapping [lo, hi]; an index can
  /// appear more than once (a triangle overlapping several buckets).
  void collect(const Vec3& lo, const Vec3& hi, std::vector<int>& out) const {
    Vec3i a, b;
    if (!bucketRange(lo, hi, a, b)) return;
    for (int k = a.z(); k <= b.z(); ++k) {
      for (int j = a.y(); j <= b.y(); ++j) {
        for (int i = a.x(); i <= b.x(); ++i) {
          const std::size_t bucket = index(i, j, k);
          out.insert(out.end(), m_triangles.begin() + m_offsets[bucket], m_triangles.begin() + m_offsets[bucket + 1]);
        }
      }
    }
  }

  std::size_t memoryBytes() const { return (m_offsets.size() + m_triangles.size()) * sizeof(int); }

 private:
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(m_counts.y()) + static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(m_counts.x()) +
           static_cast<std::size_t>(i);
  }
  /// The buckets overlapping [lo, hi], clamped to the grid; false when the box misses the grid.
  bool bucketRange(const Vec3& lo, const Vec3& hi, Vec3i& a, Vec3i& b) const {
    for (int axis = 0; axis < 3; ++axis) {
      const double from = std::floor((lo[axis] - m_origin[axis]) / m_size);
      const double to = std::floor((hi[axis] - m_origin[axis]) / m_size);
      if (!(to >= 0.0) || !(from < m_counts[axis])) return false;  // also false for NaN
      a[axis] = static_cast<int>(std::max(from, 0.0));
      b[axis] = static_cast<int>(std::min(to, static_cast<double>(m_counts[axis] - 1)));
    }
    return true;
  }

  Vec3 m_origin = Vec3::Zero();
  double m_size = 1.0;
  Vec3i m_counts = Vec3i::Ones();
  std::vector<int> m_offsets;    // bucket b lists m_triangles[m_offsets[b], m_offsets[b + 1])
  std::vector<int> m_triangles;  // triangle indices
};

}  // namespace sdfccd::bullet::detail
