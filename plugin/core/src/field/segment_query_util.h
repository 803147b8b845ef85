/// @file
/// @brief The parts of a field's segment query that every field of analytic_fields.cpp and
/// polytope_fields.cpp shares: the result's reset, the finite-input check, the maxFraction limit, and the
/// interval search of a convex function along the segment. Internal header.
#pragma once

#include <algorithm>
#include <cmath>

#include "sdfccd/ccd/segment_ccd.h"
#include "sdfccd/math_types.h"

namespace sdfccd::detail {

/// A result that says "no contact": the state every query starts from.
inline void resetSegmentResult(SegmentCcdResult& r) {
  r.state = SegmentState::Separated;
  r.fraction = 1.0;
  r.intervals.clear();
  r.normal = Vec3::Zero();
  r.point = Vec3::Zero();
  r.depth = 0.0;
}

/// Resets `outResult` and checks the input: false (with the state Failed) when an end or sigma is not finite.
inline bool startSegmentQuery(const Vec3& p0, const Vec3& p1, const SegmentCcdSettings& settings,
                              SegmentCcdResult& outResult) {
  resetSegmentResult(outResult);
  if (p0.allFinite() && p1.allFinite() && std::isfinite(settings.sigma)) return true;
  outResult.state = SegmentState::Failed;
  return false;
}

/// SegmentCcdSettings::maxFraction: a first hit after it is no contact.
inline void limitToMaxFraction(const SegmentCcdSettings& settings, SegmentCcdResult& r) {
  if (settings.mode == CcdMode::FirstHit && r.hit() && r.fraction > settings.maxFraction) resetSegmentResult(r);
}

constexpr double kGolden = 0.6180339887498949;  // (sqrt(5) - 1) / 2
constexpr int kBisections = 64;                 // halvings of [0, 1]: past the last bit of a double in [0, 1]
constexpr int kGoldenSteps = 80;                // 0.618^80 ~ 2e-17

/// The boundary in [lo, hi] of f's sublevel set {f <= 0}, given one crossing there: `insideAtLo` true when
/// f(lo) <= 0 < f(hi) (returns the last t inside), false when f(lo) > 0 >= f(hi) (the first t inside).
template <class F>
double bisectBoundary(const F& f, double lo, double hi, bool insideAtLo) {
  for (int i = 0; i < kBisections && lo < hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    const bool inside = f(mid) <= 0.0;
    (inside == insideAtLo ? lo : hi) = mid;
  }
  return insideAtLo ? lo : hi;
}

/// The interval of [0, 1] where the convex, `lipschitz`-Lipschitz f is <= 0, with f0 = f(0), f1 = f(1).
/// `needEnd` false: the end is not searched (FirstHit; `out.end` is then 1 or the start's side only).
template <class F>
bool convexSublevelInterval(const F& f, double f0, double f1, double lipschitz, bool needEnd, Interval& out) {
  const auto firstInside = [&f](double lo, double hi) { return bisectBoundary(f, lo, hi, false); };
  const auto lastInside = [&f](double lo, double hi) { return bisectBoundary(f, lo, hi, true); };
  if (f0 <= 0.0) {
    out = {0.0, f1 <= 0.0 ? 1.0 : (needEnd ? lastInside(0.0, 1.0) : 0.0)};
    return true;
  }
  if (f1 <= 0.0) {
    out = {firstInside(0.0, 1.0), 1.0};
    return true;
  }
  // Both ends outside: is there a t with f(t) <= 0? Golden-section search for the minimum, stopped as soon as
  // a point inside is found, or when the Lipschitz bound proves the bracket's minimum positive.
  if (0.5 * (f0 + f1 - lipschitz) > 0.0) return false;
  double a = 0.0, b = 1.0;
  double x1 = b - kGolden * (b - a), x2 = a + kGolden * (b - a);
  double g1 = f(x1), g2 = f(x2);
  double inside = -1.0;
  for (int i = 0; i < kGoldenSteps; ++i) {
    if (g1 <= 0.0 || g2 <= 0.0) {
      inside = g1 <= g2 ? x1 : x2;
      break;
    }
    // Convex: the minimum is in [a, x2] when g1 < g2, else in [x1, b]; on that bracket f >= g - L (b - a).
    if (std::min(g1, g2) - lipschitz * (b - a) > 0.0 || b - a < 1e-17) return false;
    if (g1 < g2) {
      b = x2;
      x2 = x1;
      g2 = g1;
      x1 = b - kGolden * (b - a);
      g1 = f(x1);
    } else {
      a = x1;
      x1 = x2;
      g1 = g2;
      x2 = a + kGolden * (b - a);
      g2 = f(x2);
    }
  }
  if (inside < 0.0) return false;
  out = {firstInside(0.0, inside), needEnd ? lastInside(inside, 1.0) : 1.0};
  return true;
}

}  // namespace sdfccd::detail
