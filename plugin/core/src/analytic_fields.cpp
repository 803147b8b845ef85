/// @file
/// @brief Closed-form segment queries of PlaneField and SphereField (see analytic_fields.h).
#include "sdfccd/analytic_fields.h"

#include <algorithm>
#include <cmath>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

void reset(SegmentCcdResult& r) {
  r.state = SegmentState::Separated;
  r.fraction = 1.0;
  r.intervals.clear();
  r.normal = Vec3::Zero();
  r.depth = 0.0;
}

bool finiteInput(const Vec3& p0, const Vec3& p1, double sigma) {
  return p0.allFinite() && p1.allFinite() && std::isfinite(sigma);
}

double clamp01(double t) {
  return std::min(1.0, std::max(0.0, t));
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
  reset(outResult);
  if (!finiteInput(p0InSdf, p1InSdf, settings.sigma)) {
    outResult.state = SegmentState::Failed;
    return;
  }
  // phi - sigma is linear along the segment: f(t) = f0 + t (f1 - f0).
  const double f0 = distance(p0InSdf) - settings.sigma;
  const double f1 = distance(p1InSdf) - settings.sigma;
  const bool all = settings.mode == CcdMode::AllIntervals;
  if (f0 <= 0.0) {  // touching counts as contact
    outResult.state = SegmentState::StartsInside;
    outResult.fraction = 0.0;
    outResult.depth = f0;
    outResult.normal = m_normal;
    if (all) outResult.intervals.append(0.0, f1 <= 0.0 ? 1.0 : clamp01(f0 / (f0 - f1)));
    return;
  }
  if (f1 > 0.0) return;  // both ends outside: a linear function has no interior minimum
  const double t = clamp01(f0 / (f0 - f1));
  outResult.state = SegmentState::Hit;
  outResult.fraction = t;
  outResult.normal = m_normal;
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
  reset(outResult);
  if (!finiteInput(p0InSdf, p1InSdf, settings.sigma)) {
    outResult.state = SegmentState::Failed;
    return;
  }
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
    if (all) outResult.intervals.append(0.0, f1 <= 0.0 ? 1.0 : (twoRoots ? clamp01(t2) : 0.0));
    return;
  }
  // p0 outside. The segment enters the ball at t1 if t1 is in [0, 1]; an end inside forces a hit (rounding).
  if (f1 > 0.0 && !(twoRoots && t1 <= 1.0 && t2 >= 0.0)) return;
  const double enter = twoRoots ? clamp01(t1) : 1.0;
  const double leave = f1 <= 0.0 ? 1.0 : clamp01(std::max(t2, enter));
  outResult.state = SegmentState::Hit;
  outResult.fraction = enter;
  outResult.normal = gradient(p0InSdf + enter * d);
  if (all) outResult.intervals.append(enter, leave);
}

}  // namespace sdfccd
