/// @file
/// @brief makePrimitiveMesh (scene_primitive.h).
#include "sdfccd/model/scene_primitive.h"

#include "sdfccd/mesh/procedural_meshes.h"

namespace sdfccd {

TriangleMesh makePrimitiveMesh(const ScenePrimitive& p) {
  if (p.type == "box") return makeBox(p.halfExtents);
  if (p.type == "sphere") return makeIcosphere(p.radius, p.subdivisions);
  if (p.type == "cylinder") return makeCylinder(p.radius, p.height);
  LathedBowlSettings bowl;
  const double factor = p.radius / bowl.rimRadius;
  bowl.rimRadius = p.radius;
  bowl.height = p.height;
  bowl.wall *= factor;
  bowl.footRadius *= factor;
  bowl.footHeight *= factor;
  return makeLathedBowl(bowl);
}

}  // namespace sdfccd
