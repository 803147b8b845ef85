/// @file
/// @brief SceneWorld: a btDiscreteDynamicsWorld built from a Scene, with our shape, algorithms and contact
/// system registered, stepped one frame at a time (paper Section 5, Fig. 9 and 10a).
///
/// @details Every body gets an SdfccdShape around its model (buildSceneModels, sdfccd/model/scene_models.h:
/// bodies whose mesh and build parameters match share one model, twenty bunnies, one field). The "ground" effect adds a
/// btStaticPlaneShape body (an analytic PlaneField to our algorithm). One frame is one Bullet step of exactly
/// scene.timestep (stepSimulation(dt, 0): no accumulator, no interpolation). Body states are reported at the centre of
/// mass (Bullet's body frame).
///
/// Tunnelling check (tunneledBodies()): a dynamic body tunnelled when its centre of mass is below the ground
/// plane, or on the other side of a static thin body ("plate": smallest extent under a quarter of the next)
/// than it started, within the plate's extent. Heuristic but exact for the shipped scenes.
///
/// Ownership: a SceneWorld owns its Bullet world, dispatcher, shapes and bodies; the models are shared
/// (std::shared_ptr<const BodyModel>); its contact system is installed in its world and removed in its destructor. References returned by world(), contacts() and body accessors live as long as the SceneWorld.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sdfccd/bullet/contact_system.h"
#include "sdfccd/model/body_model.h"
#include "sdfccd/model/scene.h"
#include "sdfccd/progress.h"

class btCollisionShape;
class btDiscreteDynamicsWorld;
class btRigidBody;

namespace sdfccd::bullet {

/// Options of SceneWorld that do not belong in the scene file.
struct SceneWorldSettings {
  std::string cacheDir;                    ///< body model cache for mesh files ("" = none)
  int threads = 0;                         ///< threads for building fields and shells (0 = all)
  std::optional<PenaltyModel> model;       ///< overrides contact.model
  std::optional<double> timestep;          ///< overrides timestep (s)
  std::optional<double> stiffness;         ///< overrides contact.stiffness (N/m)
  std::optional<bool> timeOfImpactClamp;   ///< overrides contact.toi_clamp
  std::optional<bool> useTree;             ///< overrides contact.tree
  std::optional<ForceTiming> forceTiming;  ///< overrides contact.force_timing
  std::optional<ContactSolver> solver;     ///< overrides contact.solver (solver mode)
  int shadowLinearEvery = 0;               ///< benchmarks: time a point-by-point repeat every n-th step (0: off)
  bool coherentCcd = true;                 ///< see ContactSettings::coherentCcd
  int narrowphaseThreads = 0;              ///< ContactSettings::threads (0 = all; same results for any)
  bool allowSleeping = true;               ///< false: bodies never deactivate (benchmarks time every frame)
  ProgressCallback buildProgress;          ///< fraction of the model builds done
};

/// A body's state at its centre of mass.
struct SceneBodyState {
  Vec3 position = Vec3::Zero();         ///< centre of mass, world (m)
  Quat orientation = Quat::Identity();  ///< body frame, world
  Vec3 linearVelocity = Vec3::Zero();   ///< m/s
  Vec3 angularVelocity = Vec3::Zero();  ///< rad/s
};

/// What happened in the last frame.
struct SceneFrameStats {
  double time = 0.0;              ///< s, at the end of the frame
  int contacts = 0;               ///< shell points in contact
  double penetrationCells = 0.0;  ///< largest penetration (cells)
  double ccdSeconds = 0.0;        ///< wall time in CCD queries (s)
  double stepSeconds = 0.0;       ///< wall time of the whole Bullet step (s)
  int clamps = 0;                 ///< bodies moved back to a time of impact
};

class SceneWorld {
 public:
  /// Builds the models (cached) and the world. Throws sdfccd::Error on bad meshes or settings.
  SceneWorld(const Scene& scene, const SceneWorldSettings& settings = {});
  ~SceneWorld();
  SceneWorld(const SceneWorld&) = delete;
  SceneWorld& operator=(const SceneWorld&) = delete;

  /// Advances one frame (one step of the timestep).
  void step();

  const Scene& scene() const { return m_scene; }  ///< with the overrides applied
  double timestep() const { return m_scene.timestep; }
  int frame() const { return m_frame; }
  double time() const { return m_frame * m_scene.timestep; }
  int bodyCount() const { return static_cast<int>(m_bodies.size()); }
  const std::string& bodyName(int i) const { return m_scene.bodies[static_cast<std::size_t>(i)].name; }
  bool isStatic(int i) const { return m_scene.bodies[static_cast<std::size_t>(i)].isStatic; }
  SceneBodyState bodyState(int i) const;
  const BodyModel& model(int i) const { return *m_models[static_cast<std::size_t>(i)]; }
  const std::shared_ptr<const BodyModel>& modelPtr(int i) const { return m_models[static_cast<std::size_t>(i)]; }
  btRigidBody& body(int i) { return *m_bodies[static_cast<std::size_t>(i)]; }
  btDiscreteDynamicsWorld& world() { return *m_world; }
  ContactSystem& contacts() { return *m_contacts; }

  const SceneFrameStats& lastFrame() const { return m_last; }
  double maxPenetrationCells() const { return m_maxPenetrationCells; }  ///< over all frames so far
  double ccdSeconds() const { return m_ccdSeconds; }                    ///< over all frames so far
  double stepSeconds() const { return m_stepSeconds; }                  ///< over all frames so far
  std::int64_t clamps() const { return m_clamps; }
  /// Total kinetic energy of the dynamic bodies (J).
  double kineticEnergy() const;
  /// True if any body state is NaN or infinite.
  bool hasNonFinite() const;
  /// Names of the bodies that tunnelled (see the file comment).
  std::vector<std::string> tunneledBodies() const;
  /// 64-bit FNV-1a of every body's state (the determinism check).
  std::uint64_t stateHash() const;

 private:
  struct Plate;
  Scene m_scene;
  std::unique_ptr<struct SceneWorldBullet> m_bullet;
  btDiscreteDynamicsWorld* m_world = nullptr;
  std::unique_ptr<ContactSystem> m_contacts;  // destroyed before the world (~SceneWorld)
  std::vector<std::shared_ptr<const BodyModel>> m_models;
  std::vector<btRigidBody*> m_bodies;
  std::vector<Plate> m_plates;
  int m_frame = 0;
  SceneFrameStats m_last;
  double m_maxPenetrationCells = 0.0;
  double m_ccdSeconds = 0.0;
  double m_stepSeconds = 0.0;
  std::int64_t m_clamps = 0;
};

/// The contact settings a scene asks for (effects applied: damping and rotation integrals only if listed).
ContactSettings contactSettingsFor(const Scene& scene);

/// The Bullet rigid body of `body` (one of scene.bodies) with any collision shape (ours in SceneWorld, Bullet's
/// own in a benchmark peer): the start pose of worldFromBodyAt (mass_properties.h), the mass (0 when static),
/// the principal inertia of `model`'s solid, the start velocities, no rotation without the "rotation" effect,
/// and never asleep unless `maySleep` and the scene allows it. The caller adds it to a world.
std::unique_ptr<btRigidBody> makeSceneRigidBody(const Scene& scene, const SceneBody& body, const BodyModel& model,
                                                btCollisionShape* shape, bool maySleep);

}  // namespace sdfccd::bullet
