/// @file
/// @brief Closest point on a triangle, with the feature (face, edge, vertex) it lies on. Internal header.
///
/// @details The Voronoi-region walk of Ericson, Real-Time Collision Detection, Section 5.1.5, in double. The
/// feature tells the SDF builder which angle-weighted pseudonormal decides the sign (Baerentzen & Aanaes). The
/// one closest-point routine of the core: the SDF builder, the BVH and the point shell sampler use it.
#pragma once

#include <cstdint>

#include "sdfccd/math_types.h"

namespace sdfccd::detail {

/// Where on the triangle (a, b, c) the closest point lies.
enum class TriangleFeature : std::uint8_t { Face, EdgeAB, EdgeBC, EdgeCA, VertexA, VertexB, VertexC };

/// Squared distance from p to triangle (a, b, c); writes the closest point and its feature.
inline double closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3& outClosest,
                                     TriangleFeature& outFeature) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    outClosest = a;
    outFeature = TriangleFeature::VertexA;
    return ap.squaredNorm();
  }
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) {
    outClosest = b;
    outFeature = TriangleFeature::VertexB;
    return bp.squaredNorm();
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    outClosest = a + v * ab;
    outFeature = TriangleFeature::EdgeAB;
    return (p - outClosest).squaredNorm();
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) {
    outClosest = c;
    outFeature = TriangleFeature::VertexC;
    return cp.squaredNorm();
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    outClosest = a + w * ac;
    outFeature = TriangleFeature::EdgeCA;
    return (p - outClosest).squaredNorm();
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    outClosest = b + w * (c - b);
    outFeature = TriangleFeature::EdgeBC;
    return (p - outClosest).squaredNorm();
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom;
  const double w = vc * denom;
  outClosest = a + v * ab + w * ac;
  outFeature = TriangleFeature::Face;
  return (p - outClosest).squaredNorm();
}

/// The closest point only (the point shell's projection onto the mesh).
inline Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  Vec3 q;
  TriangleFeature f;
  closestPointOnTriangle(p, a, b, c, q, f);
  return q;
}

/// Squared distance only.
inline double squaredDistanceToTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  Vec3 q;
  TriangleFeature f;
  return closestPointOnTriangle(p, a, b, c, q, f);
}

}  // namespace sdfccd::detail
