/// @file
/// @brief Procedural closed triangle meshes: box, icosphere, cylinder and a lathed "china bowl".
///
/// @details Stand-ins for scanned models and simple scene parts (the paper's china bowl, Section 3.3 Table 3
/// and Section 5 Fig. 9), shared by tests, benchmarks, the Bullet scenes and the haptics demos. Every mesh is
/// closed (watertight, manifold), its triangles counter-clockwise seen from outside (positive signed volume),
/// centred on the origin of its own frame, with +y up.
#pragma once

#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd {

/// An axis-aligned box centred on the origin, 12 triangles.
TriangleMesh makeBox(const Vec3& halfExtents);

/// A sphere of `radius` around the origin: an icosahedron subdivided `subdivisions` times (20 * 4^s triangles),
/// vertices projected onto the sphere.
TriangleMesh makeIcosphere(double radius, int subdivisions = 3);

/// A cylinder along y, centred on the origin: `segments` sides, flat caps with a centre vertex.
TriangleMesh makeCylinder(double radius, double height, int segments = 32);

/// Shape of the lathed bowl (model units).
struct LathedBowlSettings {
  double rimRadius = 1.0;    ///< outer radius at the rim
  double height = 0.6;       ///< from the bottom of the foot to the rim
  double wall = 0.06;        ///< wall thickness
  double footRadius = 0.4;   ///< outer radius of the foot ring
  double footHeight = 0.06;  ///< height of the foot ring
  int segments = 64;         ///< divisions around the axis
  int profileSamples = 24;   ///< divisions along the curved outer (and inner) wall
};

/// A china bowl revolved about y: a foot ring, a rounded outer wall, a rounded rim and an inner wall, closed at
/// both poles. Bottom of the foot at y = -height/2, rim at y = +height/2. Throws sdfccd::Error on absurd
/// settings (non-positive sizes, a wall thicker than the bowl, fewer than 3 segments).
TriangleMesh makeLathedBowl(const LathedBowlSettings& settings = {});

}  // namespace sdfccd
