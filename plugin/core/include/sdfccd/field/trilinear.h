/// @file
/// @brief Trilinear interpolation of one grid cell, written once for the grid's point queries and the CCD.
///
/// @details The eight corners are ordered 000, 100, 010, 110, 001, 101, 011, 111 (x fastest); local coordinates
/// w are in [0,1]^3. The interpolation runs along x, then y, then z. SdfGrid::interpolate() derives its gradient
/// from the same partial sums, and cell_cubic.h forms the cubic along a segment in the same order, so every
/// value of the interpolant in sdfccd agrees with every other to the bit or to rounding.
#pragma once

#include "sdfccd/math_types.h"

namespace sdfccd {

/// The partial sums of trilinear interpolation at (x, y): along x on the four edges, then along y on the two
/// faces z = 0 and z = 1.
struct TrilinearSums {
  double c00, c10, c01, c11;  ///< along x: the edges (y, z) = (0,0), (1,0), (0,1), (1,1)
  double c0, c1;              ///< along y: the faces z = 0 and z = 1
};

/// The partial sums of the corners `c` at local coordinates x, y.
inline TrilinearSums trilinearSums(const double c[8], double x, double y) {
  TrilinearSums s;
  s.c00 = c[0] + x * (c[1] - c[0]);
  s.c10 = c[2] + x * (c[3] - c[2]);
  s.c01 = c[4] + x * (c[5] - c[4]);
  s.c11 = c[6] + x * (c[7] - c[6]);
  s.c0 = s.c00 + y * (s.c10 - s.c00);
  s.c1 = s.c01 + y * (s.c11 - s.c01);
  return s;
}

/// Trilinear interpolation of the corners `c` at local coordinates w in [0,1]^3.
inline double trilinear(const double c[8], const Vec3& w) {
  const TrilinearSums s = trilinearSums(c, w.x(), w.y());
  return s.c0 + w.z() * (s.c1 - s.c0);
}

}  // namespace sdfccd
