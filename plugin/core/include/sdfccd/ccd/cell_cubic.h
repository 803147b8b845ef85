/// @file
/// @brief The trilinear interpolant of one cell restricted to a segment: a cubic (paper Section 3.1, eq. (1)).
///
/// @details Inside a cell with local coordinates w in [0,1]^3, the segment from wIn to wOut is
/// w(beta) = wIn + beta (wOut - wIn), beta in [0, 1] (eq. (1)). Each coordinate is linear in beta, so the
/// trilinear interpolant, a product of one linear factor per axis, is a cubic in beta. It is formed by
/// interpolating along x (linear in beta), then y (quadratic), then z (cubic), the same order of operations
/// as the pointwise interpolation, so cellCubic(...)(0) and trilinear(corners, wIn) agree to rounding.
#pragma once

#include "sdfccd/ccd/cubic_roots.h"
#include "sdfccd/field/trilinear.h"
#include "sdfccd/math_types.h"

namespace sdfccd {

/// The cubic g(beta) = phi(w(beta)) - sigma along the segment wIn -> wOut inside the cell (both in [0,1]^3).
inline Cubic cellCubic(const double c[8], const Vec3& wIn, const Vec3& wOut, double sigma) {
  const double x0 = wIn.x(), dx = wOut.x() - wIn.x();
  const double y0 = wIn.y(), dy = wOut.y() - wIn.y();
  const double z0 = wIn.z(), dz = wOut.z() - wIn.z();
  // Along x: four linear polynomials l0 + l1 beta.
  struct Lin {
    double l0, l1;
  };
  auto alongX = [&](double a, double b) { return Lin{a + x0 * (b - a), dx * (b - a)}; };
  const Lin e00 = alongX(c[0], c[1]), e10 = alongX(c[2], c[3]), e01 = alongX(c[4], c[5]), e11 = alongX(c[6], c[7]);
  // Along y: two quadratics q0 + q1 beta + q2 beta^2 = lo + (y0 + dy beta)(hi - lo).
  struct Quad {
    double q0, q1, q2;
  };
  auto alongY = [&](const Lin& lo, const Lin& hi) {
    const double m0 = hi.l0 - lo.l0, m1 = hi.l1 - lo.l1;
    return Quad{lo.l0 + y0 * m0, lo.l1 + y0 * m1 + dy * m0, dy * m1};
  };
  const Quad f0 = alongY(e00, e10), f1 = alongY(e01, e11);
  // Along z: the cubic f0 + (z0 + dz beta)(f1 - f0).
  const double m0 = f1.q0 - f0.q0, m1 = f1.q1 - f0.q1, m2 = f1.q2 - f0.q2;
  Cubic g;
  g.c0 = f0.q0 + z0 * m0 - sigma;
  g.c1 = f0.q1 + z0 * m1 + dz * m0;
  g.c2 = f0.q2 + z0 * m2 + dz * m1;
  g.c3 = dz * m2;
  return g;
}

}  // namespace sdfccd
