/// @file
/// @brief SceneBody: one body of a scene file (an entry of "bodies"; docs/scene-format.md).
#pragma once

#include <optional>
#include <string>

#include "sdfccd/math_types.h"
#include "sdfccd/model/scene_primitive.h"

namespace sdfccd {

struct SceneBody {
  std::string name;
  std::string mesh;  ///< resolved path of the mesh file; empty for a primitive
  std::optional<ScenePrimitive> primitive;
  std::string sdf;                      ///< optional precomputed field (with "shell"), resolved path
  std::string shell;                    ///< optional precomputed shell, resolved path
  double scale = 1.0;                   ///< uniform scale of the mesh
  double mass = 1.0;                    ///< kg (ignored for static bodies)
  Vec3 position = Vec3::Zero();         ///< of the centre of mass, world (m)
  Quat orientation = Quat::Identity();  ///< of the mesh's own axes, world
  Vec3 velocity = Vec3::Zero();         ///< m/s, of the centre of mass
  Vec3 angularVelocity = Vec3::Zero();  ///< rad/s, world
  bool isStatic = false;
  double friction = 0.5;     ///< Bullet's btRigidBody friction (combined per pair by Bullet's rule)
  double restitution = 0.0;  ///< Bullet's btRigidBody restitution (combined per pair by Bullet's rule)
  bool kinematic = false;    ///< "kinematic": infinite mass, moved each step by `velocity` (and angularVelocity)
  int points = 0;            ///< shell points (0: mesh vertices)
  /// "points" was given. A box primitive without it gets its surface sampled (body_model.h, boxHalfExtents);
  /// an explicit "points": 0 keeps the mesh's vertices (its 8 corners), as the paper-style scenes and tests ask.
  bool pointsGiven = false;
  int resolution = 64;  ///< SDF cells along the longest side
  int padding = 4;      ///< SDF padding cells
};

}  // namespace sdfccd
