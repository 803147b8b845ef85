/// @file
/// @brief Procedural meshes of the haptic scenes beyond the core's (procedural_meshes.h): the block with a
/// cylindrical through-hole of the paper's peg-in-hole example (Fig. 7, where the hole is a point shell).
#pragma once

#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd::haptics {

/// A closed, outward-oriented box of half sizes `halfExtents` centred on the origin, with a through-hole of radius
/// `holeRadius` along y on its axis, the hole a regular `segments`-gon whose vertices lie on the circle (so the wall's
/// faces come within holeRadius cos(pi / segments) of the axis). Top and bottom faces are triangulated between the
/// hole's polygon and the rectangle (its corners added). Throws sdfccd::Error on non-positive sizes, a hole that does
/// not fit inside the x-z rectangle, or segments < 3.
TriangleMesh blockWithHole(const Vec3& halfExtents, double holeRadius, int segments);

}  // namespace sdfccd::haptics
