/// @file
/// @brief GImpactPeer: a scene's bodies in a plain Bullet world that collides them with Bullet's own shapes —
/// btGImpactMeshShape (the peer of our plugin in `sdfccd bench bullet --part peer`, the 20-bunny drop, paper Fig.
/// 10a; the paper has no such comparison) or Bullet's convex fast path (btConvexHullShape of the mesh's vertices,
/// btBoxShape for box primitives; `--part modes`).
///
/// @details The same bodies as SceneWorld: each body's mesh in its body frame (BodyModel::meshInBody,
/// the triangles GImpact collides) in a rigid body made by makeSceneRigidBody (scene_world.h), as SceneWorld
/// makes its own — the same masses and inertia (from the mesh's volume, not GImpact's vertex-spread
/// estimate), start poses, velocities and sleeping policy —, the same gravity, the same ground (a
/// btStaticPlaneShape at the scene's height) and the same fixed step (stepSimulation(dt, 0)). Everything else is
/// Bullet's default: btGImpactCollisionAlgorithm:: registerAlgorithm on a btCollisionDispatcher with
/// btDefaultCollisionConfiguration, btDbvtBroadphase, btSequentialImpulseConstraintSolver (10 iterations, split impulse
/// off), friction 0.5, restitution 0, no damping, no swept-sphere CCD, the GImpact triangle margin as constructed
/// (margin() reports it). The convex world reduces each mesh to its hull's vertices (btConvexHullComputer, no
/// shrink) and keeps Bullet's default convex margin; a box primitive becomes a btBoxShape of the box's extent
/// (Bullet's box-box detector, its best stacking path).
#pragma once

#include <memory>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/model/body_model.h"
#include "sdfccd/model/scene.h"

namespace sdfccd::cli {

/// Which of Bullet's own shapes the peer world uses for the scene's bodies.
enum class PeerShape {
  GImpact,     ///< btGImpactMeshShape of the mesh (concave, exact triangles)
  ConvexHull,  ///< btConvexHullShape of the mesh's hull vertices; btBoxShape for box primitives
};

class GImpactPeer {
 public:
  /// `models[i]` is the model of scene.bodies[i] (e.g. SceneWorld::model(i)): its mesh in the body frame and
  /// its mass properties are used. `timestep` > 0 replaces the scene's. Throws sdfccd::Error if the counts differ.
  GImpactPeer(const Scene& scene, const std::vector<std::shared_ptr<const BodyModel>>& models,
              PeerShape shape = PeerShape::GImpact, double timestep = 0.0);
  ~GImpactPeer();
  GImpactPeer(const GImpactPeer&) = delete;
  GImpactPeer& operator=(const GImpactPeer&) = delete;

  /// One Bullet step of the scene's timestep (stepSimulation(dt, 0)).
  void step();

  int bodyCount() const;
  /// The body frame of body i in the world (centre of mass at the origin).
  Rigid worldFromBody(int i) const;
  double margin() const;  ///< GImpact's triangle margin, or the convex shapes' margin (m)
  double timestep() const { return m_timestep; }
  /// Convex world: the vertices of the first body's hull (0 for a box or GImpact).
  int hullVertices() const;
  /// Total kinetic energy of the dynamic bodies (J), as SceneWorld::kineticEnergy.
  double kineticEnergy() const;
  /// True if any body state is NaN or infinite.
  bool hasNonFinite() const;
  int solverIterations() const;

 private:
  std::unique_ptr<struct GImpactPeerBullet> m_bullet;
  double m_timestep = 0.001;  ///< s
};

}  // namespace sdfccd::cli
