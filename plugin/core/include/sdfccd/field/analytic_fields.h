/// @file
/// @brief PlaneField, SphereField, BoxField and CapsuleField: closed-form distance fields with the field
/// interface of field_interface.h (paper Sections 3 and 5: the ground "phi(p) = p_y"; the box and capsule serve
/// Bullet's convex shapes, beyond the paper).
///
/// @details All are exact signed distances (negative inside, 1-Lipschitz), defined everywhere, so the point
/// tree and the penalty model run against them unchanged and the ground costs no grid. intersectSegment()
/// solves phi(p0 + t (p1 - p0)) = sigma in closed form: linear for the plane, quadratic for the sphere; the
/// box and the capsule are convex, so phi along a segment is convex and its sublevel set one interval: the
/// segment is cut where it crosses the planes at which phi changes its formula (the box's face planes and
/// its mid planes; the capsule's end caps), and on each piece phi <= sigma is a linear or quadratic
/// inequality in t, solved exactly. Queries follow the policy of segment_ccd.h (touching is contact; starting
/// inside gives StartsInside at fraction 0; a zero-length segment is a point query; FirstHit leaves
/// `intervals` empty; non-finite input gives Failed).
/// The OctreeMode and CcdMethod settings do not apply (the answer is exact). Immutable; thread safe.
#pragma once

#include <algorithm>

#include "sdfccd/ccd/segment_ccd.h"
#include "sdfccd/field/field_interface.h"
#include "sdfccd/math_types.h"

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

 private:
  void intersectWholeSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                             SegmentCcdResult& outResult) const;

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

 private:
  void intersectWholeSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                             SegmentCcdResult& outResult) const;

  Vec3 m_center;
  double m_radius;
};

/// The box |p_i| <= h_i centred at the field frame's origin, axes along the frame's: the exact signed distance
/// (outside: the Euclidean distance to the box; inside: minus the distance to the nearest face).
class BoxField {
 public:
  /// Throws sdfccd::Error unless every half extent is positive and finite.
  explicit BoxField(const Vec3& halfExtents);

  const Vec3& halfExtents() const { return m_halfExtents; }  ///< model units
  bool contains(const Vec3&) const { return true; }

  double distance(const Vec3& pointInSdf) const;
  /// Outside: the unit direction from the nearest box point. Inside: the outward normal of the nearest face
  /// (ties go to the lowest axis; at the centre of a cube, +x).
  Vec3 gradient(const Vec3& pointInSdf) const;

  void intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                        SegmentCcdResult& outResult) const;

 private:
  Vec3 m_halfExtents;
};

/// The capsule of `radius` around the segment from -halfHeight to +halfHeight along axis `axis` (0 = x,
/// 1 = y, 2 = z) of the field frame: phi(p) = |p - closest point of the segment| - radius. Bullet's
/// btCapsuleShape (up axis y), btCapsuleShapeX and btCapsuleShapeZ are these with the same numbers.
class CapsuleField {
 public:
  /// Throws sdfccd::Error unless radius > 0, halfHeight >= 0 (both finite) and axis is 0, 1 or 2.
  CapsuleField(double radius, double halfHeight, int axis = 1);

  double radius() const { return m_radius; }          ///< model units
  double halfHeight() const { return m_halfHeight; }  ///< half the length of the axis segment (model units)
  int axis() const { return m_axis; }
  bool contains(const Vec3&) const { return true; }

  double distance(const Vec3& pointInSdf) const { return (pointInSdf - closestOnAxis(pointInSdf)).norm() - m_radius; }
  /// The unit direction from the nearest axis point; zero on the axis.
  Vec3 gradient(const Vec3& pointInSdf) const;

  void intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                        SegmentCcdResult& outResult) const;

 private:
  Vec3 closestOnAxis(const Vec3& pointInSdf) const {
    Vec3 c = Vec3::Zero();
    c[m_axis] = std::min(m_halfHeight, std::max(-m_halfHeight, pointInSdf[m_axis]));
    return c;
  }
  double m_radius;
  double m_halfHeight;
  int m_axis;
};

}  // namespace sdfccd
