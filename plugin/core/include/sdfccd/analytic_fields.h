/// @file
/// @brief PlaneField and SphereField: closed-form distance fields with GridField's interface (paper Sections 3
/// and 5: the ground "phi(p) = p_y").
///
/// @details Both are exact signed distances (negative inside, 1-Lipschitz), defined everywhere, so the point
/// tree and the penalty model run against them unchanged and the ground costs no grid. intersectSegment()
/// solves phi(p0 + t (p1 - p0)) = sigma in closed form: linear for the plane, quadratic for the sphere, with
/// the policy of segment_ccd.h (touching is contact; starting inside gives StartsInside at fraction 0; a
/// zero-length segment is a point query; FirstHit leaves `intervals` empty; non-finite input gives Failed).
/// The OctreeMode and CcdMethod settings do not apply (the answer is exact). Immutable; thread safe.
#pragma once

#include "sdfccd/math_types.h"
#include "sdfccd/segment_ccd.h"

namespace sdfccd {

/// phi(p) = n . p - d with unit n: the half space n . p <= d is inside.
class PlaneField {
 public:
  /// Normalizes `normal`. Throws sdfccd::Error if it is zero or non-finite, or `offset` is non-finite.
  PlaneField(const Vec3& normal, double offset);
  /// The ground of the paper's simulations: phi(p) = p_y.
  static PlaneField ground() { return PlaneField(Vec3::UnitY(), 0.0); }

  const Vec3& normal() const { return m_normal; }  ///< unit outward normal, field frame
  double offset() const { return m_offset; }       ///< model units
  bool contains(const Vec3&) const { return true; }

  double distance(const Vec3& pointInSdf) const { return m_normal.dot(pointInSdf) - m_offset; }
  Vec3 gradient(const Vec3&) const { return m_normal; }

  void intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                        SegmentCcdResult& outResult) const;
  SegmentCcdResult intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf,
                                    const SegmentCcdSettings& settings) const {
    SegmentCcdResult r;
    intersectSegment(p0InSdf, p1InSdf, settings, r);
    return r;
  }

 private:
  Vec3 m_normal;
  double m_offset;
};

/// phi(p) = |p - c| - r: the ball is inside.
class SphereField {
 public:
  /// Throws sdfccd::Error unless the centre is finite and the radius positive and finite.
  SphereField(const Vec3& center, double radius);

  const Vec3& center() const { return m_center; }  ///< field frame
  double radius() const { return m_radius; }       ///< model units
  bool contains(const Vec3&) const { return true; }

  double distance(const Vec3& pointInSdf) const { return (pointInSdf - m_center).norm() - m_radius; }
  /// The unit radial direction; zero at the centre.
  Vec3 gradient(const Vec3& pointInSdf) const;

  void intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                        SegmentCcdResult& outResult) const;
  SegmentCcdResult intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf,
                                    const SegmentCcdSettings& settings) const {
    SegmentCcdResult r;
    intersectSegment(p0InSdf, p1InSdf, settings, r);
    return r;
  }

 private:
  Vec3 m_center;
  double m_radius;
};

}  // namespace sdfccd
