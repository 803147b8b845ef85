/// @file
/// @brief ConvexPolytopeField and TriangleSetField (see polytope_fields.h): distances and the convex segment
/// query.
#include "sdfccd/field/polytope_fields.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "field/segment_query_util.h"
#include "mesh/triangle_distance.h"
#include "sdfccd/error.h"

namespace sdfccd {
namespace {

/// How far above sigma still counts as touching: rounding. A point crossing a zero-thickness triangle with
/// sigma = 0 touches it at one t only, where the computed distance is a few ulps above zero.
double touchTolerance(const Vec3& p0, const Vec3& p1, double reach) {
  return 1e-12 * (1.0 + std::max({p0.cwiseAbs().maxCoeff(), p1.cwiseAbs().maxCoeff(), std::abs(reach)}));
}

void checkTriangles(const std::vector<Vec3>& vertices, const std::vector<TriangleIndices>& triangles, double radius,
                    const char* who) {
  if (triangles.empty()) throw Error(std::string(who) + ": no triangles");
  if (!(radius >= 0.0) || !std::isfinite(radius)) throw Error(std::string(who) + ": radius must be finite and >= 0");
  for (const Vec3& v : vertices) {
    if (!v.allFinite()) throw Error(std::string(who) + ": a vertex is not finite");
  }
  const int count = static_cast<int>(vertices.size());
  for (const TriangleIndices& t : triangles) {
    for (int i : t) {
      if (i < 0 || i >= count) throw Error(std::string(who) + ": a triangle's vertex index is out of range");
    }
  }
}

Vec3 triangleAreaVector(const std::vector<Vec3>& v, const TriangleIndices& t) {
  return 0.5 * (v[static_cast<std::size_t>(t[1])] - v[static_cast<std::size_t>(t[0])])
                   .cross(v[static_cast<std::size_t>(t[2])] - v[static_cast<std::size_t>(t[0])]);
}

/// The segment query of a convex field grown by `radius` (ConvexPolytopeField, RevolvedConvexField): phi is
/// convex along the segment, so its contact set is one interval.
template <class Field>
void convexFieldSegmentQuery(const Field& field, double radius, const Vec3& p0, const Vec3& p1,
                             const SegmentCcdSettings& settings, SegmentCcdResult& outResult) {
  if (!detail::startSegmentQuery(p0, p1, settings, outResult)) return;
  const Vec3 d = p1 - p0;
  const double level = settings.sigma + touchTolerance(p0, p1, settings.sigma + radius);
  const auto f = [&](double t) { return field.distance(p0 + t * d) - level; };
  const double f0 = f(0.0);
  const double f1 = f(1.0);
  const bool all = settings.mode == CcdMode::AllIntervals;
  Interval span;
  if (!detail::convexSublevelInterval(f, f0, f1, d.norm(), all, span)) return;
  outResult.state = span.begin > 0.0 ? SegmentState::Hit : SegmentState::StartsInside;
  outResult.fraction = span.begin;
  outResult.point = p0 + span.begin * d;
  outResult.depth = span.begin > 0.0 ? 0.0 : field.distance(p0) - settings.sigma;
  outResult.normal = field.gradient(outResult.point);
  if (all) outResult.intervals.append(span.begin, span.end);
  detail::limitToMaxFraction(settings, outResult);
}

}  // namespace

// ---- ConvexPolytopeField ----

ConvexPolytopeField::ConvexPolytopeField(std::vector<Vec3> vertices, std::vector<TriangleIndices> triangles,
                                         double radius)
    : m_vertices(std::move(vertices)), m_triangles(std::move(triangles)), m_radius(radius) {
  checkTriangles(m_vertices, m_triangles, radius, "ConvexPolytopeField");
  for (const TriangleIndices& t : m_triangles) {
    const Vec3 area = triangleAreaVector(m_vertices, t);
    if (!(area.norm() > 0.0)) throw Error("ConvexPolytopeField: a triangle has zero area");
    m_normals.push_back(area.normalized());
    m_offsets.push_back(m_normals.back().dot(m_vertices[static_cast<std::size_t>(t[0])]));
  }
}

double ConvexPolytopeField::largestPlaneValue(const Vec3& p, int& outFace) const {
  double largest = -std::numeric_limits<double>::infinity();
  outFace = 0;
  for (std::size_t k = 0; k < m_normals.size(); ++k) {
    const double value = m_normals[k].dot(p) - m_offsets[k];
    if (value > largest) {
      largest = value;
      outFace = static_cast<int>(k);
    }
  }
  return largest;
}

double ConvexPolytopeField::outsideDistance(const Vec3& p, Vec3& outClosest) const {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < m_triangles.size(); ++k) {
    // Only faces that p is in front of can hold the nearest point of a convex polytope.
    if (m_normals[k].dot(p) - m_offsets[k] < 0.0) continue;
    const TriangleIndices& t = m_triangles[k];
    Vec3 q;
    detail::TriangleFeature feature;
    const double d2 = detail::closestPointOnTriangle(p, m_vertices[static_cast<std::size_t>(t[0])],
                                                     m_vertices[static_cast<std::size_t>(t[1])],
                                                     m_vertices[static_cast<std::size_t>(t[2])], q, feature);
    if (d2 < best) {
      best = d2;
      outClosest = q;
    }
  }
  return std::sqrt(best);
}

double ConvexPolytopeField::distance(const Vec3& pointInSdf) const {
  int face = 0;
  const double plane = largestPlaneValue(pointInSdf, face);
  if (plane <= 0.0) return plane - m_radius;  // inside: the nearest face plane
  Vec3 closest;
  return outsideDistance(pointInSdf, closest) - m_radius;
}

Vec3 ConvexPolytopeField::gradient(const Vec3& pointInSdf) const {
  int face = 0;
  const double plane = largestPlaneValue(pointInSdf, face);
  if (plane > 0.0) {
    Vec3 closest = pointInSdf;
    const double d = outsideDistance(pointInSdf, closest);
    if (d > 0.0) return (pointInSdf - closest) / d;
  }
  return m_normals[static_cast<std::size_t>(face)];
}

void ConvexPolytopeField::intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                                           SegmentCcdResult& outResult) const {
  convexFieldSegmentQuery(*this, m_radius, p0InSdf, p1InSdf, settings, outResult);
}

// ---- TriangleSetField ----

TriangleSetField::TriangleSetField(std::vector<Vec3> vertices, std::vector<TriangleIndices> triangles, double radius,
                                   double thickness, const Vec3& outside)
    : m_vertices(std::move(vertices)), m_radius(radius), m_thickness(thickness) {
  checkTriangles(m_vertices, triangles, radius, "TriangleSetField");
  if (!(thickness >= 0.0) || !std::isfinite(thickness) || !outside.allFinite()) {
    throw Error("TriangleSetField: thickness must be finite and >= 0, the outside point finite");
  }
  for (const TriangleIndices& t : triangles) {
    const Vec3 area = triangleAreaVector(m_vertices, t);
    if (!(area.norm() > 0.0)) continue;
    m_triangles.push_back(t);
    const Vec3& a = m_vertices[static_cast<std::size_t>(t[0])];
    const Vec3 n = area.normalized();
    m_normals.push_back(n.dot(outside - a) < 0.0 ? Vec3(-n) : n);
    Box3 box;
    for (int i : t) {
      box.extend(m_vertices[static_cast<std::size_t>(i)]);
      box.extend(m_vertices[static_cast<std::size_t>(i)] - thickness * m_normals.back());
    }
    m_boxes.push_back(box);
  }
  if (m_triangles.empty()) throw Error("TriangleSetField: every triangle has zero area");
}

double TriangleSetField::triangleDistance(int k, const Vec3& p, Vec3& outClosest, bool& outOverFace) const {
  const TriangleIndices& t = m_triangles[static_cast<std::size_t>(k)];
  const Vec3& a = m_vertices[static_cast<std::size_t>(t[0])];
  detail::TriangleFeature feature;
  const double d =
      std::sqrt(detail::closestPointOnTriangle(p, a, m_vertices[static_cast<std::size_t>(t[1])],
                                               m_vertices[static_cast<std::size_t>(t[2])], outClosest, feature));
  // Over the face (its edges included, shared with a coplanar neighbour): the nearest point is straight below.
  const double height = m_normals[static_cast<std::size_t>(k)].dot(p - a);
  outOverFace = feature == detail::TriangleFeature::Face || d - std::abs(height) <= 1e-12 * (1.0 + d);
  return outOverFace && height < 0.0 && height >= -m_thickness ? -d : d;
}

int TriangleSetField::nearestTriangle(const Vec3& p, double& outDistance) const {
  int nearest = 0;
  outDistance = std::numeric_limits<double>::infinity();
  for (int k = 0; k < static_cast<int>(m_triangles.size()); ++k) {
    // The box's distance is a lower bound of the triangle's (signed distances only go below it inside the box).
    if (m_boxes[static_cast<std::size_t>(k)].exteriorDistance(p) >= outDistance) continue;
    Vec3 q;
    bool overFace = false;
    const double d = triangleDistance(k, p, q, overFace);
    if (d < outDistance) {
      outDistance = d;
      nearest = k;
    }
  }
  return nearest;
}

Vec3 TriangleSetField::awayFromTriangle(int k, const Vec3& p) const {
  Vec3 q;
  bool overFace = false;
  const double d = std::abs(triangleDistance(k, p, q, overFace));
  // Over the face: its outward normal (exact even where p - q is all rounding); beside it: away from it.
  if (overFace || !(d > 0.0)) return m_normals[static_cast<std::size_t>(k)];
  return (p - q) / d;
}

bool TriangleSetField::behindInterval(int k, const Vec3& p0, const Vec3& d, Interval& out) const {
  if (!(m_thickness > 0.0)) return false;
  const TriangleIndices& t = m_triangles[static_cast<std::size_t>(k)];
  const Vec3& n = m_normals[static_cast<std::size_t>(k)];
  double begin = 0.0, end = 1.0;
  // Keeps the t where c + g . p(t) >= 0 (Liang-Barsky clipping of the segment by a half-space).
  auto keep = [&](double c, const Vec3& g) {
    const double at0 = c + g.dot(p0);
    const double slope = g.dot(d);
    if (slope == 0.0) {
      if (at0 < 0.0) end = -1.0;
      return;
    }
    const double root = -at0 / slope;
    if (slope > 0.0) {
      begin = std::max(begin, root);
    } else {
      end = std::min(end, root);
    }
  };
  const Vec3& a = m_vertices[static_cast<std::size_t>(t[0])];
  keep(n.dot(a), -n);               // n . (p - a) <= 0: behind the face
  keep(m_thickness - n.dot(a), n);  // n . (p - a) >= -thickness
  for (int e = 0; e < 3; ++e) {     // inside the prism over the triangle
    const Vec3& from = m_vertices[static_cast<std::size_t>(t[static_cast<std::size_t>(e)])];
    const Vec3& to = m_vertices[static_cast<std::size_t>(t[static_cast<std::size_t>((e + 1) % 3)])];
    const Vec3& other = m_vertices[static_cast<std::size_t>(t[static_cast<std::size_t>((e + 2) % 3)])];
    Vec3 inward = n.cross(to - from);
    if (inward.dot(other - from) < 0.0) inward = -inward;
    keep(-inward.dot(from), inward);
  }
  if (!(begin <= end)) return false;
  out = {begin, end};
  return true;
}

bool TriangleSetField::jumpReachable(const Vec3& c0, const Vec3& c1, double reach) const {
  if (!(m_thickness > 0.0)) return false;  // no slabs: 1-Lipschitz everywhere
  Box3 near(c0.cwiseMin(c1), c0.cwiseMax(c1));
  near.min().array() -= reach;
  near.max().array() += reach;
  for (std::size_t k = 0; k < m_triangles.size(); ++k) {
    if (!near.intersects(m_boxes[k])) continue;  // the slab (inside its box) is out of reach
    const Vec3& a = m_vertices[static_cast<std::size_t>(m_triangles[k][0])];
    if (m_normals[k].dot(c0 - a) < 0.0 || m_normals[k].dot(c1 - a) < 0.0) return true;
  }
  return false;
}

double TriangleSetField::distance(const Vec3& pointInSdf) const {
  double d = 0.0;
  nearestTriangle(pointInSdf, d);
  return d - m_radius;
}

Vec3 TriangleSetField::gradient(const Vec3& pointInSdf) const {
  double d = 0.0;
  return awayFromTriangle(nearestTriangle(pointInSdf, d), pointInSdf);
}

void TriangleSetField::intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                                        SegmentCcdResult& outResult) const {
  if (!detail::startSegmentQuery(p0InSdf, p1InSdf, settings, outResult)) return;
  const Vec3 d = p1InSdf - p0InSdf;
  const double length = d.norm();
  const double reach = settings.sigma + m_radius;  // contact: within `reach` of a triangle, or behind it
  const double level = reach + touchTolerance(p0InSdf, p1InSdf, reach);
  Box3 sweep(p0InSdf.cwiseMin(p1InSdf), p0InSdf.cwiseMax(p1InSdf));
  sweep.min().array() -= std::max(reach, 0.0);
  sweep.max().array() += std::max(reach, 0.0);
  const bool all = settings.mode == CcdMode::AllIntervals;
  // Each triangle's contact set along the segment: where its unsigned distance is <= reach (one interval: the
  // distance to a triangle is convex along a segment), and the part behind its face (one interval: a convex
  // prism). The union is sorted and merged; the first hit is the earliest begin, its triangle gives the normal.
  std::vector<Interval> parts;
  int firstTriangle = -1;
  double first = std::numeric_limits<double>::infinity();
  auto add = [&](int k, const Interval& span) {
    if (span.begin < first) {
      first = span.begin;
      firstTriangle = k;
    }
    if (all) parts.push_back(span);
  };
  for (int k = 0; k < static_cast<int>(m_triangles.size()); ++k) {
    if (!sweep.intersects(m_boxes[static_cast<std::size_t>(k)])) continue;
    Vec3 q;
    bool overFace = false;
    const auto f = [&](double t) { return std::abs(triangleDistance(k, p0InSdf + t * d, q, overFace)) - level; };
    Interval span;
    if (detail::convexSublevelInterval(f, f(0.0), f(1.0), length, all, span)) add(k, span);
    if (behindInterval(k, p0InSdf, d, span)) add(k, span);
    if (!all && first == 0.0) break;  // FirstHit: nothing comes before the start
  }
  if (firstTriangle < 0) return;
  outResult.state = first > 0.0 ? SegmentState::Hit : SegmentState::StartsInside;
  outResult.fraction = first;
  outResult.point = p0InSdf + first * d;
  outResult.depth = first > 0.0 ? 0.0 : std::min(0.0, distance(p0InSdf) - settings.sigma);
  outResult.normal = awayFromTriangle(firstTriangle, outResult.point);
  if (all) {
    std::sort(parts.begin(), parts.end(), [](const Interval& a, const Interval& b) { return a.begin < b.begin; });
    for (const Interval& part : parts) outResult.intervals.append(part.begin, part.end);
  }
  detail::limitToMaxFraction(settings, outResult);
}

// ---- RevolvedConvexField ----

RevolvedConvexField::RevolvedConvexField(std::vector<Eigen::Vector2d> profile, int axis, double radius)
    : m_profile(std::move(profile)), m_axis(axis), m_radius(radius) {
  if (m_profile.size() < 3 || axis < 0 || axis > 2 || !(radius >= 0.0) || !std::isfinite(radius)) {
    throw Error("RevolvedConvexField: needs 3 or more profile points, an axis 0..2 and a finite radius >= 0");
  }
  for (const Eigen::Vector2d& q : m_profile) {
    if (!q.allFinite() || q.x() < 0.0) throw Error("RevolvedConvexField: profile points need rho >= 0, finite");
  }
  if (m_profile.front().x() != 0.0 || m_profile.back().x() != 0.0) {
    throw Error("RevolvedConvexField: the profile must start and end on the axis");
  }
}

double RevolvedConvexField::profileDistance(const Eigen::Vector2d& q, Eigen::Vector2d* outGradient) const {
  double best = std::numeric_limits<double>::infinity();
  bool inside = true;
  Eigen::Vector2d away = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k + 1 < m_profile.size(); ++k) {
    const Eigen::Vector2d& a = m_profile[k];
    const Eigen::Vector2d e = m_profile[k + 1] - a;
    const double length2 = e.squaredNorm();
    if (!(length2 > 0.0)) continue;
    const Eigen::Vector2d r = q - a;
    if (e.x() * r.y() - e.y() * r.x() > 0.0) inside = false;  // left of a clockwise edge: outside
    const double s = std::clamp(r.dot(e) / length2, 0.0, 1.0);
    const Eigen::Vector2d diff = r - s * e;
    const double d = diff.norm();
    if (d < best) {
      best = d;
      away = d > 0.0 ? Eigen::Vector2d(diff / d) : Eigen::Vector2d(-e.y(), e.x()).normalized();
    }
  }
  if (inside) {  // the nearest edge's outward normal (the right of a clockwise edge)
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k + 1 < m_profile.size(); ++k) {
      const Eigen::Vector2d e = m_profile[k + 1] - m_profile[k];
      if (!(e.squaredNorm() > 0.0)) continue;
      const Eigen::Vector2d n = Eigen::Vector2d(-e.y(), e.x()).normalized();  // left of a clockwise edge
      const double depth = -n.dot(q - m_profile[k]);                          // >= 0 inside
      if (depth < nearest) {
        nearest = depth;
        away = n;
      }
    }
    best = -nearest;
  }
  if (outGradient) *outGradient = away;
  return best;
}

double RevolvedConvexField::distance(const Vec3& p) const {
  Vec3 radial = p;
  radial[m_axis] = 0.0;
  return profileDistance(Eigen::Vector2d(radial.norm(), p[m_axis]), nullptr) - m_radius;
}

Vec3 RevolvedConvexField::gradient(const Vec3& p) const {
  Vec3 radial = p;
  radial[m_axis] = 0.0;
  const double rho = radial.norm();
  Eigen::Vector2d g;
  profileDistance(Eigen::Vector2d(rho, p[m_axis]), &g);
  const Vec3 unitRadial = rho > 0.0 ? Vec3(radial / rho) : Vec3::Unit((m_axis + 1) % 3);
  return g.x() * unitRadial + g.y() * Vec3::Unit(m_axis);
}

void RevolvedConvexField::intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                                           SegmentCcdResult& outResult) const {
  convexFieldSegmentQuery(*this, m_radius, p0InSdf, p1InSdf, settings, outResult);
}

RevolvedConvexField cylinderField(double cylinderRadius, double halfHeight, int axis, double rounding) {
  return RevolvedConvexField(
      {{0.0, halfHeight}, {cylinderRadius, halfHeight}, {cylinderRadius, -halfHeight}, {0.0, -halfHeight}}, axis,
      rounding);
}

RevolvedConvexField coneField(double coneRadius, double height, int axis, double rounding) {
  return RevolvedConvexField({{0.0, 0.5 * height}, {coneRadius, -0.5 * height}, {0.0, -0.5 * height}}, axis, rounding);
}

}  // namespace sdfccd
