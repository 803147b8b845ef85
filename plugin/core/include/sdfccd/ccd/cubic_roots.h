/// @file
/// @brief Where a cubic is <= 0 on [0, 1]: the robust root finder of the exact segment CCD (Section 3.1).
///
/// @details The paper solves the cell's cubic with Cardano's formulas. Cardano loses accuracy when the
/// leading coefficient is small (segments nearly parallel to a cell face) and near double roots (grazing
/// contacts), exactly where a missed contact hurts. Instead the roots of the derivative (a quadratic, solved
/// with the cancellation-free formula) split [0, 1] into at most three pieces on which the cubic is monotone;
/// on each piece the sign at the two ends decides whether it holds no root, is entirely <= 0, or holds exactly
/// one root, which a safeguarded Newton iteration (falling back to bisection) brackets to ~1e-15. Every
/// endpoint reported is a point where the evaluated cubic is <= 0, so the answer errs on the side of contact.
///
/// Touching counts as contact: a double root where the cubic touches 0 from above (a grazing contact) lies
/// at a critical point, is evaluated there and reported as a zero-length interval.
///
/// Written by hand: neither Eigen (its PolynomialSolver is an unsupported module using eigenvalues) nor the
/// standard library offers a bracketing solver with these guarantees.
#pragma once

#include <algorithm>
#include <cmath>

#include "sdfccd/tolerances.h"

namespace sdfccd {

/// g(x) = c0 + c1 x + c2 x^2 + c3 x^3.
struct Cubic {
  double c0 = 0.0, c1 = 0.0, c2 = 0.0, c3 = 0.0;

  double operator()(double x) const { return ((c3 * x + c2) * x + c1) * x + c0; }
  double derivative(double x) const { return (3.0 * c3 * x + 2.0 * c2) * x + c1; }
};

/// Real roots of a x^2 + b x + c = 0 strictly inside (0, 1), sorted; returns their count (0..2).
/// a = 0 degrades to the linear equation; a tiny a is handled by the stable formula (the large root leaves
/// (0, 1) and the small one is computed as c / q without cancellation).
inline int quadraticRootsInUnit(double a, double b, double c, double outRoots[2]) {
  int count = 0;
  auto keep = [&](double r) {
    if (r > 0.0 && r < 1.0) outRoots[count++] = r;
  };
  if (a == 0.0) {
    if (b != 0.0) keep(-c / b);
    return count;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return 0;  // no real root (or a double root lost to rounding: the cubic is monotone there)
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  if (q == 0.0) {  // b == 0 and disc == 0, hence c == 0: double root at 0
    return 0;
  }
  const double r1 = q / a, r2 = c / q;
  keep(std::min(r1, r2));
  if (r1 != r2) keep(std::max(r1, r2));
  return count;
}

/// The boundary point in [lo, hi] between g > 0 and g <= 0 of a cubic monotone on [lo, hi], with
/// g(lo) and g(hi) on opposite sides (exactly one of them <= 0). Returns a point where g <= 0 (the side
/// that is in contact), within ~1e-15 of the true root. Safeguarded Newton (as in rtsafe): a Newton step
/// that leaves the bracket or shrinks too slowly is replaced by bisection.
inline double cubicBoundaryRoot(const Cubic& g, double lo, double hi, double gLo) {
  // `in` is the end with g <= 0, `out` the end with g > 0; both move inwards.
  double in = gLo <= 0.0 ? lo : hi;
  double out = gLo <= 0.0 ? hi : lo;
  double step = hi - lo, lastStep = step;
  double x = 0.5 * (lo + hi);
  for (int iteration = 0; iteration < 128; ++iteration) {
    const double gx = g(x);
    if (gx <= 0.0) {
      in = x;
    } else {
      out = x;
    }
    if (gx == 0.0 || std::abs(out - in) <= 2.5e-16) return in;
    const double slope = g.derivative(x);
    const double bLo = std::min(in, out), bHi = std::max(in, out);
    const double newton = slope != 0.0 ? x - gx / slope : x;
    lastStep = step;
    if (!(newton > bLo && newton < bHi) || std::abs(2.0 * gx) > std::abs(lastStep * slope)) {
      step = 0.5 * (bHi - bLo);
      x = bLo + step;
    } else {
      step = gx / slope;
      x = newton;
    }
    if (std::abs(step) <= tolerance::kNewtonMinStep || x == in || x == out) break;
  }
  // Newton converges from one side; step towards `in` by growing amounts until g <= 0, so the returned
  // point is in contact and within a few ulps of the root.
  if (x > std::min(in, out) && x < std::max(in, out) && g(x) <= 0.0) return x;
  const double toIn = in > x ? 1.0 : -1.0;
  for (double e = tolerance::kRootNudgeFirst; e < tolerance::kRootNudgeLast; e *= 4.0) {
    const double y = x + toIn * e;
    if ((toIn > 0.0 ? y >= in : y <= in)) break;
    if (g(y) <= 0.0) return y;
  }
  return in;
}

/// Visits every maximal sub-interval [a, b] of [0, 1] with g <= 0 in increasing order (a == b for a point
/// where g touches 0). Calls visit(a, b); when visit returns false the search stops (first-hit mode).
/// The first interval begins at the smallest x in [0, 1] with g(x) <= 0.
template <class Visit>
void cubicNonPositiveIntervals(const Cubic& g, Visit&& visit) {
  double breaks[4];
  breaks[0] = 0.0;
  const int critical = quadraticRootsInUnit(3.0 * g.c3, 2.0 * g.c2, g.c1, breaks + 1);
  const int pieces = critical + 1;
  breaks[pieces] = 1.0;

  // Intervals are merged across piece boundaries before they are handed out.
  bool open = false;
  double openBegin = 0.0, openEnd = 0.0;
  double gLo = g(0.0);
  for (int p = 0; p < pieces; ++p) {
    const double lo = breaks[p], hi = breaks[p + 1];
    const double gHi = p + 1 == pieces ? g(1.0) : g(hi);
    double a, b;
    if (gLo <= 0.0 && gHi <= 0.0) {
      a = lo;
      b = hi;
    } else if (gLo <= 0.0) {
      a = lo;
      b = cubicBoundaryRoot(g, lo, hi, gLo);
    } else if (gHi <= 0.0) {
      a = cubicBoundaryRoot(g, lo, hi, gLo);
      b = hi;
    } else {
      gLo = gHi;
      continue;
    }
    gLo = gHi;
    if (open && a <= openEnd) {
      openEnd = std::max(openEnd, b);
    } else {
      if (open && !visit(openBegin, openEnd)) return;
      open = true;
      openBegin = a;
      openEnd = b;
    }
  }
  if (open) visit(openBegin, openEnd);
}

}  // namespace sdfccd
