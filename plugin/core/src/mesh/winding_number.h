/// @file
/// @brief FastWindingNumber: the generalized winding number of a triangle soup, evaluated hierarchically.
/// Internal header of the SDF builder.
///
/// @details w(p) = sum over triangles of the signed solid angle / 4 pi (Jacobson, Kavan & Sorkine-Hornung,
/// "Robust inside-outside segmentation using generalized winding numbers", 2013): 1 inside a closed outward
/// mesh, 0 outside, and a smooth, robust in-between across holes and open boundaries. Far clusters are
/// replaced by their first-order dipole (Barill, Dickson, Schmidt, Levin & Jacobson, "Fast winding numbers
/// for soups and clouds", 2018): a BVH subtree whose triangles all lie within radius R of its area-weighted
/// centre c counts as N . (c - p) / (4 pi |c - p|^3), N the sum of area vectors, when |c - p| > beta R.
#pragma once

#include <vector>

#include "sdfccd/math_types.h"
#include "triangle_bvh.h"

namespace sdfccd::detail {

class FastWindingNumber {
 public:
  /// `beta` > 1: larger is more accurate and slower (2 gives errors well under 0.01 away from the surface).
  FastWindingNumber(const TriangleBvh& bvh, double beta);

  /// The winding number at p (model frame). Thread-safe.
  double operator()(const Vec3& p) const;

  std::size_t memoryBytes() const { return m_clusters.capacity() * sizeof(Cluster); }

  /// Exact signed solid angle of triangle (a, b, c) seen from p, divided by 4 pi (Van Oosterom & Strackee).
  static double triangleWinding(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

 private:
  struct Cluster {
    Vec3 centre;           ///< area-weighted centroid
    Vec3 areaVector;       ///< sum of (b - a) x (c - a) / 2 over the subtree
    double radius2 = 0.0;  ///< (beta * radius)^2: far field beyond this squared distance
  };
  const TriangleBvh& m_bvh;
  std::vector<Cluster> m_clusters;  // one per BVH node
};

}  // namespace sdfccd::detail
