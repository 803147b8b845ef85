/// @file
/// @brief Closed-form segment queries of PlaneField, SphereField, BoxField and CapsuleField (see analytic_fields.h).
#include "sdfccd/field/analytic_fields.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "field/segment_query_util.h"
#include "sdfccd/error.h"

namespace sdfccd {
namespace {

double clamp01(double t) {
  return std::min(1.0, std::max(0.0, t));
}

/// The part of [lo, hi] where a t^2 + 2 b t + c <= 0 (a >= 0: convex, so one interval or none). Returns false
/// when it is empty.
bool convexQuadraticAtMostZero(double a, double b, double c, double lo, double hi, Interval& out) {
  double begin = lo;
  double end = hi;
  if (a > 0.0) {
    const double disc = b * b - a * c;
    if (disc < 0.0) return false;
    const double q = -(b + std::copysign(std::sqrt(disc), b));  // stable roots q / a and c / q
    const double r1 = q != 0.0 ? q / a : 0.0;
    const double r2 = q != 0.0 ? c / q : 0.0;
    begin = std::max(lo, std::min(r1, r2));
    end = std::min(hi, std::max(r1, r2));
  } else if (b != 0.0) {  // linear: 2 b t + c <= 0
    const double root = -c / (2.0 * b);
    if (b > 0.0) {
      end = std::min(hi, root);
    } else {
      begin = std::max(lo, root);
    }
  } else if (c > 0.0) {
    return false;
  }
  if (!(begin <= end)) return false;
  out = {begin, end};
  return true;
}

/// The pieces of [0, 1] between the sorted cut fractions in (0, 1), handed to `solvePiece(lo, hi, mid)`,
/// which returns the part of its piece where phi <= sigma; the union (one interval, phi being convex along
/// the segment) is the span of the parts.
template <class SolvePiece>
bool spanOfPieces(std::array<double, 12>& cuts, int cutCount, SolvePiece solvePiece, Interval& out) {
  std::sort(cuts.begin(), cuts.begin() + cutCount);
  bool any = false;
  double lo = 0.0;
  for (int k = 0; k <= cutCount; ++k) {
    const double hi = k < cutCount ? cuts[static_cast<std::size_t>(k)] : 1.0;
    Interval part;
    if (hi >= lo && solvePiece(lo, hi, 0.5 * (lo + hi), part)) {
      out = any ? Interval{std::min(out.begin, part.begin), std::max(out.end, part.end)} : part;
      any = true;
    }
    lo = hi;
  }
  return any;
}

/// Fills `outResult` from the contact interval of a convex field along the segment (found or not), with
/// f0, f1 = phi - sigma at the ends. Rounding: an end inside with no interval found forces a contact there.
template <class Field>
void finishConvexQuery(const Field& field, const Vec3& p0, const Vec3& p1, double f0, double f1, bool found,
                       Interval span, bool all, SegmentCcdResult& outResult) {
  if (f0 <= 0.0) {  // starting inside (touching counts as contact)
    outResult.state = SegmentState::StartsInside;
    outResult.fraction = 0.0;
    outResult.depth = f0;
    outResult.normal = field.gradient(p0);
    outResult.point = p0;
    if (all) outResult.intervals.append(0.0, f1 <= 0.0 ? 1.0 : (found ? clamp01(span.end) : 0.0));
    return;
  }
  if (!found && f1 > 0.0) return;
  const double enter = found ? clamp01(span.begin) : 1.0;
  const double leave = f1 <= 0.0 ? 1.0 : clamp01(std::max(span.end, enter));
  outResult.state = SegmentState::Hit;
  outResult.fraction = enter;
  outResult.point = p0 + enter * (p1 - p0);
  outResult.normal = field.gradient(outResult.point);
  if (all) outResult.intervals.append(enter, leave);
}

}  // namespace

PlaneField::PlaneField(const Vec3& normal, double offset) : m_normal(normal), m_offset(offset) {
  const double length = normal.norm();
  if (!normal.allFinite() || !(length > 0.0) || !std::isfinite(offset)) {
    throw Error("PlaneField: the normal must be finite and non-zero and the offset finite");
  }
  m_normal /= length;
}

void PlaneField::intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                                  SegmentCcdResult& outResult) const {
  intersectWholeSegment(p0InSdf, p1InSdf, settings, outResult);
  detail::limitToMaxFraction(settings, outResult);
}

void PlaneField::intersectWholeSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                                       SegmentCcdResult& outResult) const {
  if (!detail::startSegmentQuery(p0InSdf, p1InSdf, settings, outResult)) return;
  // phi - sigma is linear along the segment: f(t) = f0 + t (f1 - f0).
  const double f0 = distance(p0InSdf) - settings.sigma;
  const double f1 = distance(p1InSdf) - settings.sigma;
  const bool all = settings.mode == CcdMode::AllIntervals;
  if (f0 <= 0.0) {  // touching counts as contact
    outResult.state = SegmentState::StartsInside;
    outResult.fraction = 0.0;
    outResult.depth = f0;
    outResult.normal = m_normal;
    outResult.point = p0InSdf;
    if (all) outResult.intervals.append(0.0, f1 <= 0.0 ? 1.0 : clamp01(f0 / (f0 - f1)));
    return;
  }
  if (f1 > 0.0) return;  // both ends outside: a linear function has no interior minimum
  const double t = clamp01(f0 / (f0 - f1));
  outResult.state = SegmentState::Hit;
  outResult.fraction = t;
  outResult.normal = m_normal;
  outResult.point = p0InSdf + t * (p1InSdf - p0InSdf);
  if (all) outResult.intervals.append(t, 1.0);
}

SphereField::SphereField(const Vec3& center, double radius) : m_center(center), m_radius(radius) {
  if (!center.allFinite() || !(radius > 0.0) || !std::isfinite(radius)) {
    throw Error("SphereField: the centre must be finite and the radius positive and finite");
  }
}

Vec3 SphereField::gradient(const Vec3& pointInSdf) const {
  const Vec3 d = pointInSdf - m_center;
  const double length = d.norm();
  return length > 0.0 ? Vec3(d / length) : Vec3::Zero();
}

void SphereField::intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                                   SegmentCcdResult& outResult) const {
  intersectWholeSegment(p0InSdf, p1InSdf, settings, outResult);
  detail::limitToMaxFraction(settings, outResult);
}

void SphereField::intersectWholeSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                                        SegmentCcdResult& outResult) const {
  if (!detail::startSegmentQuery(p0InSdf, p1InSdf, settings, outResult)) return;
  const bool all = settings.mode == CcdMode::AllIntervals;
  const double f0 = distance(p0InSdf) - settings.sigma;
  const double f1 = distance(p1InSdf) - settings.sigma;
  // phi <= sigma  <=>  |p(t) - c|^2 <= R^2 with R = r + sigma:  a t^2 + 2 b t + cc <= 0.
  const double big = m_radius + settings.sigma;
  const Vec3 d = p1InSdf - p0InSdf;
  const Vec3 m = p0InSdf - m_center;
  const double a = d.squaredNorm();
  const double b = d.dot(m);
  const double cc = m.squaredNorm() - big * big;
  const double disc = b * b - a * cc;
  // The roots t1 <= t2 (stable form); only meaningful when a > 0 and disc >= 0.
  double t1 = 0.0;
  double t2 = 0.0;
  const bool twoRoots = big >= 0.0 && a > 0.0 && disc >= 0.0;
  if (twoRoots) {
    const double q = -(b + std::copysign(std::sqrt(disc), b));
    if (q != 0.0) {
      t1 = std::min(q / a, cc / q);
      t2 = std::max(q / a, cc / q);
    } else {  // b = 0 and disc = 0: a tangent at t = 0
      t1 = t2 = 0.0;
    }
  }
  if (f0 <= 0.0) {  // starting inside (touching counts as contact)
    outResult.state = SegmentState::StartsInside;
    outResult.fraction = 0.0;
    outResult.depth = f0;
    outResult.normal = gradient(p0InSdf);
    outResult.point = p0InSdf;
    if (all) outResult.intervals.append(0.0, f1 <= 0.0 ? 1.0 : (twoRoots ? clamp01(t2) : 0.0));
    return;
  }
  // p0 outside. The segment enters the ball at t1 if t1 is in [0, 1]; an end inside forces a hit (rounding).
  if (f1 > 0.0 && !(twoRoots && t1 <= 1.0 && t2 >= 0.0)) return;
  const double enter = twoRoots ? clamp01(t1) : 1.0;
  const double leave = f1 <= 0.0 ? 1.0 : clamp01(std::max(t2, enter));
  outResult.state = SegmentState::Hit;
  outResult.fraction = enter;
  outResult.point = p0InSdf + enter * d;
  outResult.normal = gradient(outResult.point);
  if (all) outResult.intervals.append(enter, leave);
}

BoxField::BoxField(const Vec3& halfExtents) : m_halfExtents(halfExtents) {
  if (!halfExtents.allFinite() || !(halfExtents.minCoeff() > 0.0)) {
    throw Error("BoxField: the half extents must be positive and finite");
  }
}

double BoxField::distance(const Vec3& pointInSdf) const {
  const Vec3 q = pointInSdf.cwiseAbs() - m_halfExtents;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

Vec3 BoxField::gradient(const Vec3& pointInSdf) const {
  const Vec3 q = pointInSdf.cwiseAbs() - m_halfExtents;
  Vec3 sign;
  for (int i = 0; i < 3; ++i) sign[i] = pointInSdf[i] < 0.0 ? -1.0 : 1.0;
  const Vec3 outside = q.cwiseMax(0.0);
  const double length = outside.norm();
  if (length > 0.0) return Vec3(sign.cwiseProduct(outside) / length);
  int nearest = 0;
  q.maxCoeff(&nearest);
  Vec3 g = Vec3::Zero();
  g[nearest] = sign[nearest];
  return g;
}

void BoxField::intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                                SegmentCcdResult& outResult) const {
  if (!detail::startSegmentQuery(p0InSdf, p1InSdf, settings, outResult)) return;
  const double sigma = settings.sigma;
  const Vec3 d = p1InSdf - p0InSdf;
  // Cuts where a coordinate crosses -h, 0 or +h: between them each q_i = |p_i| - h_i is linear in t and keeps
  // its sign, so phi is either max_i q_i (inside: linear pieces) or |q_active| (outside: a quadratic's root).
  std::array<double, 12> cuts{};
  int cutCount = 0;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) continue;
    for (double plane : {-m_halfExtents[i], 0.0, m_halfExtents[i]}) {
      const double t = (plane - p0InSdf[i]) / d[i];
      if (t > 0.0 && t < 1.0) cuts[static_cast<std::size_t>(cutCount++)] = t;
    }
  }
  auto solvePiece = [&](double lo, double hi, double mid, Interval& part) {
    double qa[3], qb[3];  // q_i(t) = qa + qb t on the piece
    bool outside[3];
    bool anyOutside = false;
    for (int i = 0; i < 3; ++i) {
      const double sign = p0InSdf[i] + mid * d[i] < 0.0 ? -1.0 : 1.0;
      qa[i] = sign * p0InSdf[i] - m_halfExtents[i];
      qb[i] = sign * d[i];
      outside[i] = qa[i] + qb[i] * mid > 0.0;
      anyOutside = anyOutside || outside[i];
    }
    if (!anyOutside) {  // max_i q_i(t) <= sigma: every q_i(t) <= sigma, each a half line
      double begin = lo;
      double end = hi;
      for (int i = 0; i < 3; ++i) {
        Interval half;
        if (!convexQuadraticAtMostZero(0.0, 0.5 * qb[i], qa[i] - sigma, lo, hi, half)) return false;
        begin = std::max(begin, half.begin);
        end = std::min(end, half.end);
      }
      if (!(begin <= end)) return false;
      part = {begin, end};
      return true;
    }
    // phi > 0 inside this piece: no contact for sigma <= 0 (phi = 0 only at an end of the piece, which the
    // neighbouring inside piece holds exactly; the quadratic's double root there is only sqrt(eps) accurate).
    if (sigma <= 0.0) return false;
    double a = 0.0, b = 0.0, c = -sigma * sigma;  // sum of the outside q_i^2 - sigma^2
    for (int i = 0; i < 3; ++i) {
      if (!outside[i]) continue;
      a += qb[i] * qb[i];
      b += qa[i] * qb[i];
      c += qa[i] * qa[i];
    }
    return convexQuadraticAtMostZero(a, b, c, lo, hi, part);
  };
  Interval span;
  const bool found = spanOfPieces(cuts, cutCount, solvePiece, span);
  finishConvexQuery(*this, p0InSdf, p1InSdf, distance(p0InSdf) - sigma, distance(p1InSdf) - sigma, found, span,
                    settings.mode == CcdMode::AllIntervals, outResult);
  detail::limitToMaxFraction(settings, outResult);
}

CapsuleField::CapsuleField(double radius, double halfHeight, int axis)
    : m_radius(radius), m_halfHeight(halfHeight), m_axis(axis) {
  if (!(radius > 0.0) || !std::isfinite(radius) || !(halfHeight >= 0.0) || !std::isfinite(halfHeight) || axis < 0 ||
      axis > 2) {
    throw Error("CapsuleField: radius must be positive, halfHeight >= 0 (both finite) and axis 0, 1 or 2");
  }
}

Vec3 CapsuleField::gradient(const Vec3& pointInSdf) const {
  const Vec3 away = pointInSdf - closestOnAxis(pointInSdf);
  const double length = away.norm();
  return length > 0.0 ? Vec3(away / length) : Vec3::Zero();
}

void CapsuleField::intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                                    SegmentCcdResult& outResult) const {
  if (!detail::startSegmentQuery(p0InSdf, p1InSdf, settings, outResult)) return;
  const double big = m_radius + settings.sigma;  // phi <= sigma <=> distance to the axis segment <= big
  const Vec3 d = p1InSdf - p0InSdf;
  const double da = d[m_axis];
  // Cuts where the axial coordinate crosses the end caps: between them the closest axis point is either the
  // projection (the distance to the axis line) or one end (the distance to a point), each a quadratic in t.
  std::array<double, 12> cuts{};
  int cutCount = 0;
  if (da != 0.0) {
    for (double cap : {-m_halfHeight, m_halfHeight}) {
      const double t = (cap - p0InSdf[m_axis]) / da;
      if (t > 0.0 && t < 1.0) cuts[static_cast<std::size_t>(cutCount++)] = t;
    }
  }
  auto solvePiece = [&](double lo, double hi, double mid, Interval& part) {
    if (big < 0.0) return false;
    const double axial = p0InSdf[m_axis] + mid * da;
    Vec3 m = p0InSdf;  // from the closest axis point (an end, or the projection: the axial part dropped)
    Vec3 dm = d;
    if (axial > m_halfHeight) {
      m[m_axis] -= m_halfHeight;
    } else if (axial < -m_halfHeight) {
      m[m_axis] += m_halfHeight;
    } else {
      m[m_axis] = 0.0;
      dm[m_axis] = 0.0;
    }
    return convexQuadraticAtMostZero(dm.squaredNorm(), dm.dot(m), m.squaredNorm() - big * big, lo, hi, part);
  };
  Interval span;
  const bool found = spanOfPieces(cuts, cutCount, solvePiece, span);
  finishConvexQuery(*this, p0InSdf, p1InSdf, distance(p0InSdf) - settings.sigma, distance(p1InSdf) - settings.sigma,
                    found, span, settings.mode == CcdMode::AllIntervals, outResult);
  detail::limitToMaxFraction(settings, outResult);
}

}  // namespace sdfccd
