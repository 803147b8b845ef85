/// @file
/// @brief Point shells on the surfaces of analytic shapes (box, sphere, capsule): the points a Bullet convex
/// shape brings to point-vs-field CCD (paper Section 5 checks every pair both ways, "each body in each role";
/// beyond the paper, which has only meshes).
///
/// @details The points lie exactly on the surface, with its exact outward normals, spread at about `spacing`:
/// - box: the lattice of (n_x + 1)(n_y + 1)(n_z + 1) points with n_i = ceil(2 h_i / spacing), those on the
///   surface; corners and edges are included (a tilted box lands on them), with the normalized sum of the
///   normals of the faces they lie on;
/// - sphere: a Fibonacci spiral of ceil(4 pi r^2 / spacing^2) points (at least 12);
/// - capsule: rings on the cylinder (the caps' rims included) and a Fibonacci half spiral on each cap.
/// If the spacing would give more than `maxPoints` points it is grown until it does not. Deterministic.
///
/// Point areas (stiffness per unit area: point_shell.h) sum to the closed-form surface area: box points carry their
/// trapezoid-rule share of each face they lie on (edges and corners share several faces); sphere and cap
/// spiral points carry equal-area bands (4 pi r^2 / N); capsule ring points share 2 pi r (2 halfHeight) by the
/// trapezoid rule along the axis, and a capsule with halfHeight = 0 shares 4 pi r^2 evenly.
#pragma once

#include "sdfccd/math_types.h"
#include "sdfccd/shell/point_shell.h"

namespace sdfccd {

/// How densely an analytic surface is sampled.
struct AnalyticShellSettings {
  double spacing = 0.01;  ///< distance between neighbouring points (model units, > 0)
  int maxPoints = 20000;  ///< cap on the number of points (>= 12)
};

/// The surface of the box |p_i| <= h_i. Throws sdfccd::Error on non-positive or non-finite sizes or settings.
PointShell boxShell(const Vec3& halfExtents, const AnalyticShellSettings& settings);
/// The sphere of `radius` around the origin. Throws sdfccd::Error as boxShell.
PointShell sphereShell(double radius, const AnalyticShellSettings& settings);
/// The capsule of CapsuleField (analytic_fields.h): radius around the axis segment from -halfHeight to
/// +halfHeight along coordinate `axis`. Throws sdfccd::Error as boxShell, or if axis is not 0, 1 or 2.
PointShell capsuleShell(double radius, double halfHeight, int axis, const AnalyticShellSettings& settings);

}  // namespace sdfccd
