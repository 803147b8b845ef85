/// @file
/// @brief ConvexPolytopeField and TriangleSetField: exact distance fields of triangle sets, with the field
/// interface of field_interface.h (beyond the paper: they let Bullet's convex hulls, cylinders, cones and
/// static triangle meshes and terrain meet our point shells).
///
/// @details
/// - ConvexPolytopeField: the signed distance to a closed convex polytope (given by its outward triangles)
///   grown by a rounding radius r: phi(p) = d(p, P) - r, d the exact signed distance (outside: the Euclidean
///   distance to the nearest triangle; inside: minus the distance to the nearest face plane). This is a
///   Bullet convex shape with its collision margin: the hull of its margin-free support points, grown by the
///   margin.
/// - TriangleSetField: the distance to a set of triangles minus a radius (Bullet's margin of a concave shape).
///   Open meshes and terrain have no inside, so a point that comes within sigma + r of any triangle is a
///   contact, and the normal points to the side it came from: the side of a given `outside` point (the shell
///   body's centre), to which every triangle's normal is turned. A point that went past a triangle's face (a
///   resting body sinks a little) is inside, at minus its distance, up to a `thickness` behind it: beyond, the
///   triangle is a wall seen from its other side again.
///
/// Segment queries are exact up to rounding: along a segment p(t) the distance to a convex set (a polytope, or
/// one triangle) is convex in t, so its sublevel set {phi <= sigma} is one interval. It is found by a
/// golden-section search for a point inside (stopped early by the 1-Lipschitz lower bound when none can be)
/// and bisection of both ends to the last bit of t. A TriangleSetField unions the intervals of its triangles
/// (each triangle's found the same way, after a bounding-box test). Policy as segment_ccd.h (touching is
/// contact; starting inside gives StartsInside at fraction 0; FirstHit leaves `intervals` empty; non-finite
/// input gives Failed). Both are 1-Lipschitz and defined everywhere. Immutable; thread safe.
#pragma once

#include <array>
#include <vector>

#include "sdfccd/ccd/segment_ccd.h"
#include "sdfccd/field/field_culling_bounds.h"
#include "sdfccd/field/field_interface.h"
#include "sdfccd/math_types.h"

/// Expands X(Field) for the two fields of this header: the rigid CCD, the contact query and the penalty model
/// are instantiated for them too (not the haptic renderers, which meet grid and analytic fields only).
#define SDFCCD_FOR_EACH_TRIANGLE_FIELD(X) X(ConvexPolytopeField) X(TriangleSetField) X(RevolvedConvexField)

namespace sdfccd {

/// Triangles as vertex indices (counter-clockwise seen from outside, for a polytope).
using TriangleIndices = std::array<int, 3>;

/// The convex polytope of `triangles` (closed, outward, counter-clockwise) grown by `radius` (see the file
/// comment).
class ConvexPolytopeField {
 public:
  /// Throws sdfccd::Error (one line) on no triangles, an index out of range, a non-finite vertex, a triangle of
  /// zero area or a negative or non-finite radius.
  ConvexPolytopeField(std::vector<Vec3> vertices, std::vector<TriangleIndices> triangles, double radius);

  const std::vector<Vec3>& vertices() const { return m_vertices; }
  const std::vector<TriangleIndices>& triangles() const { return m_triangles; }
  double radius() const { return m_radius; }
  bool contains(const Vec3&) const { return true; }

  double distance(const Vec3& pointInSdf) const;
  /// Outside: the unit direction from the nearest polytope point. Inside: the outward normal of the nearest face.
  Vec3 gradient(const Vec3& pointInSdf) const;

  void intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                        SegmentCcdResult& outResult) const;

 private:
  /// The largest face-plane value n . p - d (> 0 outside) and the face it belongs to.
  double largestPlaneValue(const Vec3& p, int& outFace) const;
  /// The distance from an outside point to the polytope's surface, and the nearest surface point.
  double outsideDistance(const Vec3& p, Vec3& outClosest) const;

  std::vector<Vec3> m_vertices;
  std::vector<TriangleIndices> m_triangles;
  std::vector<Vec3> m_normals;    // per triangle, unit outward
  std::vector<double> m_offsets;  // per triangle: n . p = offset on its plane
  double m_radius;
};

/// The distance to a set of triangles, minus `radius`, one-sided with a `thickness` (see the file comment).
class TriangleSetField {
 public:
  /// `outside`: a point on the side the shell comes from (its body's centre): each triangle's normal is turned
  /// towards it, and a point up to `thickness` behind a triangle (over its face) is inside, at minus its
  /// distance, with that normal as gradient. thickness 0: the plain unsigned distance.
  /// Triangles of zero area are dropped (their edges belong to their neighbours). Throws sdfccd::Error (one line)
  /// when no triangle is left, on an index out of range, a non-finite vertex or `outside`, or a negative or
  /// non-finite radius or thickness.
  TriangleSetField(std::vector<Vec3> vertices, std::vector<TriangleIndices> triangles, double radius,
                   double thickness = 0.0, const Vec3& outside = Vec3::Zero());

  const std::vector<Vec3>& vertices() const { return m_vertices; }
  const std::vector<TriangleIndices>& triangles() const { return m_triangles; }
  double radius() const { return m_radius; }
  double thickness() const { return m_thickness; }
  bool contains(const Vec3&) const { return true; }
  /// Not continuous: phi drops from +d to -d (d <= thickness) where a point enters a slab through its back face
  /// or beside an open edge. Per triangle, phi_k(q) >= udist_k(q) - r - 2 min(thickness, depth of q in slab k), so
  /// from a point p in front of triangle k's plane (or in its slab) the drop is at most 2 |q - p| (q can be no
  /// deeper than |q - p|): phi(q) >= phi(p) - 3 |q - p|, the `lipschitz` 3. From behind a plane and outside that
  /// slab it is up to 2 thickness, the `jump`, which the culling adds only where jumpReachable() says so.
  FieldCullingBounds cullingBounds() const {
    FieldCullingBounds bounds;
    bounds.lipschitz = 3.0;
    bounds.jump = 2.0 * m_thickness;
    return bounds;
  }
  /// False when every point within `reach` of the segment [c0, c1] is bounded from both ends with `lipschitz`
  /// alone: no triangle whose slab box comes within `reach` of the segment's box has c0 or c1 behind its plane.
  /// (True is conservative: the culling then adds the jump.)
  bool jumpReachable(const Vec3& c0, const Vec3& c1, double reach) const;

  double distance(const Vec3& pointInSdf) const;
  /// Over a triangle's face: its normal, turned to the outside. Beside it: the unit direction from its nearest
  /// point (edge or vertex).
  Vec3 gradient(const Vec3& pointInSdf) const;

  void intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                        SegmentCcdResult& outResult) const;

 private:
  /// The signed distance to triangle k (negative up to `thickness` behind its face), its nearest point and
  /// whether that point is on the face.
  double triangleDistance(int k, const Vec3& p, Vec3& outClosest, bool& outOverFace) const;
  /// The triangle of least signed distance to p, and that distance.
  int nearestTriangle(const Vec3& p, double& outDistance) const;
  /// The gradient of triangle k's distance at p (see gradient()).
  Vec3 awayFromTriangle(int k, const Vec3& p) const;
  /// The part of the segment within the slab up to `thickness` behind triangle k's face; false when none.
  bool behindInterval(int k, const Vec3& p0, const Vec3& d, Interval& out) const;

  std::vector<Vec3> m_vertices;
  std::vector<TriangleIndices> m_triangles;
  std::vector<Vec3> m_normals;  // per triangle, unit, towards `outside`
  std::vector<Box3> m_boxes;    // per triangle, grown by the thickness
  double m_radius;
  double m_thickness;
};

/// A convex solid of revolution about axis `axis` (0 = x, 1 = y, 2 = z) of the field frame, grown by
/// `radius`: its meridian profile is the polyline `profile` of (distance from the axis, height) points, from
/// a point on the axis round to a point on the axis, clockwise (outward on the right), the axis closing it.
/// The exact signed distance of a solid of revolution is the 2D signed distance of (rho, height) to its
/// profile, so this is exact and O(profile) per point. cylinderField() and coneField() make Bullet's.
class RevolvedConvexField {
 public:
  /// Throws sdfccd::Error (one line) on fewer than 3 profile points, ends off the axis, a point with a
  /// negative or non-finite coordinate, an axis not 0..2, or a negative or non-finite radius.
  RevolvedConvexField(std::vector<Eigen::Vector2d> profile, int axis, double radius);

  const std::vector<Eigen::Vector2d>& profile() const { return m_profile; }
  int axis() const { return m_axis; }
  double radius() const { return m_radius; }
  bool contains(const Vec3&) const { return true; }

  double distance(const Vec3& pointInSdf) const;
  /// Outside: the unit direction from the nearest surface point; inside: the nearest profile edge's outward
  /// normal (on the axis, a radial direction chosen once).
  Vec3 gradient(const Vec3& pointInSdf) const;

  void intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                        SegmentCcdResult& outResult) const;

 private:
  /// The 2D signed distance of (rho, height) to the profile and the 2D gradient.
  double profileDistance(const Eigen::Vector2d& q, Eigen::Vector2d* outGradient) const;

  std::vector<Eigen::Vector2d> m_profile;
  int m_axis;
  double m_radius;
};

/// The cylinder |p_axis| <= halfHeight, rho <= cylinderRadius, grown by `rounding` (Bullet's btCylinderShape:
/// its margin-free half extents and its margin).
RevolvedConvexField cylinderField(double cylinderRadius, double halfHeight, int axis, double rounding);
/// The cone with apex at +height/2 on `axis` and base of `coneRadius` at -height/2, grown by `rounding`
/// (Bullet's btConeShape and its margin).
RevolvedConvexField coneField(double coneRadius, double height, int axis, double rounding);

}  // namespace sdfccd
