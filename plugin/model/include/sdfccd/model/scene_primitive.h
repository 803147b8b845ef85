/// @file
/// @brief ScenePrimitive: a procedural body shape of a scene file (key "primitive") instead of a mesh file, and
/// the one function that turns it into a mesh (for the simulation, its benchmark peers and the renderer alike).
#pragma once

#include <string>

#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd {

/// A procedural body shape (procedural_meshes.h), in model units.
struct ScenePrimitive {
  std::string type;                        ///< "box", "sphere", "cylinder" or "bowl"
  Vec3 halfExtents = Vec3::Constant(0.5);  ///< box (model units)
  double radius = 0.5;                     ///< sphere, cylinder; the bowl's rim radius (model units)
  double height = 1.0;                     ///< cylinder; the bowl's height (model units)
  int subdivisions = 5;                    ///< sphere: 10,242 vertices, the shell; it rolls smoothly in both modes
};

/// The mesh of `primitive`, centred as procedural_meshes.h builds it; the bowl is the default lathed bowl scaled to
/// the rim radius (its height as given). Throws sdfccd::Error on absurd sizes.
TriangleMesh makePrimitiveMesh(const ScenePrimitive& primitive);

}  // namespace sdfccd
