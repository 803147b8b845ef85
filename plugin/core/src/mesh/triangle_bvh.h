/// @file
/// @brief TriangleBvh: a binary bounding-box hierarchy over triangles for closest-point and range queries.
/// Internal header of the SDF builder.
///
/// @details Built top-down by median split of centroids along the widest axis, leaves of up to 4 triangles.
/// Triangles are stored in leaf order (position p holds mesh triangle triangleIndex(p)), so a subtree covers
/// a contiguous range of positions. Immutable after construction: any number of threads may query it.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd::detail {

class TriangleBvh {
 public:
  struct Node {
    Vec3 lo, hi;     ///< box of the subtree's triangles (model units)
    int start = 0;   ///< first triangle position of the subtree
    int count = 0;   ///< number of triangle positions of the subtree
    int right = -1;  ///< index of the right child (the left child is this index + 1); -1 for a leaf
  };

  explicit TriangleBvh(const TriangleMesh& mesh);

  const std::vector<Node>& nodes() const { return m_nodes; }
  std::size_t size() const { return m_a.size(); }
  int triangleIndex(int position) const { return m_order[position]; }
  const Vec3& a(int position) const { return m_a[position]; }
  const Vec3& b(int position) const { return m_b[position]; }
  const Vec3& c(int position) const { return m_c[position]; }
  const Vec3& boxLo(int position) const { return m_boxLo[position]; }
  const Vec3& boxHi(int position) const { return m_boxHi[position]; }
  double squaredDistance(const Vec3& p, int position) const;

  /// The closest triangle position to p and its squared distance. ioBest2 may carry a known upper bound
  /// (with ioPosition the triangle achieving it) and is lowered to the exact minimum.
  void closest(const Vec3& p, double& ioBest2, int& ioPosition) const;

  /// Appends every triangle position whose box lies within distance `radius` of the box [lo, hi].
  void collectNearBox(const Vec3& lo, const Vec3& hi, double radius, std::vector<int>& out) const;

  std::size_t memoryBytes() const;

  static double squaredBoxDistance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
    const Vec3 gap = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
    return gap.squaredNorm();
  }

 private:
  int build(int start, int count, std::vector<Vec3>& centroids);

  std::vector<Node> m_nodes;
  std::vector<int> m_order;
  std::vector<Vec3> m_a, m_b, m_c, m_boxLo, m_boxHi;
};

}  // namespace sdfccd::detail
