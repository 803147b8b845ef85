/// @file
/// @brief SceneWorld (see scene_world.h).
#include "sdfccd/bullet/scene_world.h"

#include <LinearMath/btTransformUtil.h>
#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cmath>
#include <sstream>

#include "common/bullet_conversions.h"
#include "step/contact_step.h"
#include "sdfccd/bullet/contact_solver.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "sdfccd/error.h"
#include "sdfccd/fnv1a.h"
#include "sdfccd/model/scene_models.h"

namespace sdfccd::bullet {

/// Bullet's objects, owned together and destroyed in the right order. The constraint solver is the scene's
/// contact.solver (contact_solver.h).
struct SceneWorldBullet {
  explicit SceneWorldBullet(ContactSolver kind) : solver(makeContactSolver(kind)) {
    configureContactSolver(world.getSolverInfo(), kind);
  }
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  std::unique_ptr<btConstraintSolver> solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, solver.get(), &configuration};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  ~SceneWorldBullet() {
    for (auto& b : bodies) world.removeRigidBody(b.get());
  }
};

struct SceneWorld::Plate {
  Vec3 center = Vec3::Zero();
  Vec3 normal = Vec3::UnitY();
  Vec3 axisU = Vec3::UnitX(), axisV = Vec3::UnitZ();
  double halfU = 0.0, halfV = 0.0;
  std::vector<int> startSide;  // per body: sign of normal . (com - center)
};

using detail::toBt;
using detail::toVec3;

namespace {

std::string vectorText(const Vec3& v) {
  std::ostringstream text;
  text << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return text.str();
}

/// A Scene built in code skips the parser's checks: the state that enters the world is checked here, and each
/// defect is a one-line error naming the body and the field.
void checkSceneState(const Scene& scene) {
  if (!std::isfinite(scene.timestep) || !(scene.timestep > 0)) {
    throw Error("SceneWorld: timestep must be finite and > 0 (got " + std::to_string(scene.timestep) + ")");
  }
  if (!scene.gravity.allFinite()) throw Error("SceneWorld: gravity is not finite " + vectorText(scene.gravity));
  if (!std::isfinite(scene.groundHeight)) throw Error("SceneWorld: ground height is not finite");
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const SceneBody& b = scene.bodies[i];
    const std::string who = "SceneWorld: body '" + b.name + "' (bodies[" + std::to_string(i) + "]): ";
    if (!b.position.allFinite()) throw Error(who + "position is not finite " + vectorText(b.position));
    if (!b.orientation.coeffs().allFinite() || !(b.orientation.norm() > 0.5)) {
      throw Error(who + "orientation is not a finite unit quaternion");
    }
    if (!b.velocity.allFinite()) throw Error(who + "velocity is not finite " + vectorText(b.velocity));
    if (!b.angularVelocity.allFinite()) {
      throw Error(who + "angular velocity is not finite " + vectorText(b.angularVelocity));
    }
    if (!std::isfinite(b.scale) || !(b.scale > 0)) throw Error(who + "scale must be finite and > 0");
    if (!b.isStatic && !b.kinematic && (!std::isfinite(b.mass) || !(b.mass > 0))) {
      throw Error(who + "mass must be finite and > 0 (got " + std::to_string(b.mass) + ")");
    }
  }
}

/// The first non-finite part of a body's state that Bullet would integrate, or nullptr if all are finite.
const char* nonFiniteState(const btRigidBody& b) {
  const btTransform& t = b.getWorldTransform();
  if (!toVec3(t.getOrigin()).allFinite()) return "position";
  for (int r = 0; r < 3; ++r) {
    if (!toVec3(t.getBasis()[r]).allFinite()) return "orientation";
  }
  if (!toVec3(b.getLinearVelocity()).allFinite()) return "linear velocity";
  if (!toVec3(b.getAngularVelocity()).allFinite()) return "angular velocity";
  if (!std::isfinite(b.getInvMass()) || !toVec3(b.getInvInertiaDiagLocal()).allFinite()) return "mass";
  if (!toVec3(b.getTotalForce()).allFinite() || !toVec3(b.getTotalTorque()).allFinite()) return "applied force";
  if (!toVec3(b.getGravity()).allFinite()) return "gravity";
  return nullptr;
}

}  // namespace

ContactSettings contactSettingsFor(const Scene& scene) {
  ContactSettings s;
  s.penalty.model = scene.contact.model;
  s.penalty.stiffness = scene.contact.stiffness;
  s.penalty.stiffnessPerArea = scene.contact.stiffnessPerArea;
  s.penalty.damping = scene.contact.damping;
  s.penalty.dampingRatio = scene.contact.dampingRatio;
  s.penalty.dampingRatioFromRestitution = scene.contact.dampingFromRestitution;
  s.penalty.frictionFromBodies = scene.contact.frictionFromBodies;
  s.penalty.frictionModel = scene.contact.frictionModel;
  s.penalty.subintervals = scene.contact.subintervals;
  s.penalty.enableDamping = scene.has("damping");
  s.penalty.enableRotation = scene.has("rotation");
  s.penalty.enableFriction = scene.has("friction");
  s.penalty.friction = scene.contact.friction;
  s.penalty.direction = scene.contact.direction;
  s.forceTiming = scene.contact.forceTiming;
  s.timeOfImpactClamp = scene.contact.timeOfImpactClamp;
  s.toiDepthCells = scene.contact.toiDepthCells;
  s.useTree = scene.contact.useTree;
  s.mode = scene.contact.mode;
  return s;
}

std::unique_ptr<btRigidBody> makeSceneRigidBody(const Scene& scene, const SceneBody& b, const BodyModel& model,
                                                btCollisionShape* shape, bool maySleep) {
  const Rigid worldFromBody = worldFromBodyAt(model.modelFromBody(), b.position, b.orientation);
  const Quat q(worldFromBody.linear());
  btTransform start(btQuaternion(btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w())),
                    toBt(Vec3(worldFromBody.translation())));
  const bool fixedMass = b.isStatic || b.kinematic;
  const btScalar mass = fixedMass ? btScalar(0) : btScalar(b.mass);
  const btVector3 inertia = fixedMass ? btVector3(0, 0, 0) : toBt(model.principalInertia(double(mass)));
  btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, shape, inertia);
  info.m_startWorldTransform = start;
  info.m_friction = btScalar(b.friction);
  info.m_restitution = btScalar(b.restitution);
  auto body = std::make_unique<btRigidBody>(info);
  if (b.kinematic) {
    // Moved by SceneWorld::step; Bullet derives its velocity from the moves (saveKinematicState).
    body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    body->setActivationState(DISABLE_DEACTIVATION);
  } else if (!b.isStatic) {
    body->setLinearVelocity(toBt(b.velocity));
    if (scene.has("rotation")) {
      body->setAngularVelocity(toBt(b.angularVelocity));
    } else {
      body->setAngularFactor(btVector3(0, 0, 0));  // no rotation effect: the bodies only translate
    }
    if (!maySleep || !scene.sleeping) body->setActivationState(DISABLE_DEACTIVATION);
  }
  return body;
}

SceneWorld::SceneWorld(const Scene& scene, const SceneWorldSettings& settings) : m_scene(scene) {
  if (settings.model) m_scene.contact.model = *settings.model;
  if (settings.timestep) {
    if (!(*settings.timestep > 0) || !std::isfinite(*settings.timestep)) {
      throw Error("SceneWorld: timestep must be finite and > 0 (got " + std::to_string(*settings.timestep) + ")");
    }
    m_scene.timestep = *settings.timestep;
  }
  if (settings.stiffness) {
    if (!(*settings.stiffness > 0) || !std::isfinite(*settings.stiffness)) throw Error("stiffness must be positive");
    m_scene.contact.stiffness = *settings.stiffness;
    m_scene.contact.stiffnessPerArea = 0.0;  // a per-point stiffness: the paper's law
  }
  if (settings.timeOfImpactClamp) m_scene.contact.timeOfImpactClamp = *settings.timeOfImpactClamp;
  if (settings.useTree) m_scene.contact.useTree = *settings.useTree;
  if (settings.forceTiming) m_scene.contact.forceTiming = *settings.forceTiming;
  if (settings.solver) {
    // As the scene reader refuses contact.solver in penalty mode: penalty mode answers its contacts itself.
    if (m_scene.contact.mode != SdfccdContactMode::Solver)
      throw Error("solver: a constraint solver applies only in solver mode (this scene's contact.mode is penalty)");
    m_scene.contact.solver = *settings.solver;
  }
  checkSceneState(m_scene);

  // Models: one per distinct mesh + parameters.
  SceneModelSettings modelSettings;
  modelSettings.cacheDir = settings.cacheDir;
  modelSettings.threads = settings.threads;
  modelSettings.progress = settings.buildProgress;
  m_models = buildSceneModels(m_scene, modelSettings);

  // Penalty mode answers its contacts itself: Bullet's default solver, which sees none of them, as before.
  m_bullet = std::make_unique<SceneWorldBullet>(
      m_scene.contact.mode == SdfccdContactMode::Solver ? m_scene.contact.solver : ContactSolver::SequentialImpulse);
  m_world = &m_bullet->world;
  m_world->setGravity(m_scene.has("gravity") ? toBt(m_scene.gravity) : btVector3(0, 0, 0));
  ContactSettings contactSettings = contactSettingsFor(m_scene);
  contactSettings.coherentCcd = settings.coherentCcd;
  contactSettings.threads = settings.narrowphaseThreads;
  m_contacts = std::make_unique<ContactSystem>(*m_world, contactSettings);
  detail::ContactSystemAccess::step(*m_contacts).data().shadowLinearEvery = settings.shadowLinearEvery;

  if (m_scene.has("ground")) {
    auto plane = std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), btScalar(m_scene.groundHeight));
    btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, plane.get());
    info.m_friction = btScalar(m_scene.groundFriction);
    info.m_restitution = btScalar(m_scene.groundRestitution);
    auto ground = std::make_unique<btRigidBody>(info);
    m_world->addRigidBody(ground.get());
    m_bullet->shapes.push_back(std::move(plane));
    m_bullet->bodies.push_back(std::move(ground));
  }
  for (std::size_t i = 0; i < m_scene.bodies.size(); ++i) {
    const SceneBody& b = m_scene.bodies[i];
    const BodyModel& model = *m_models[i];
    auto shape = std::make_unique<SdfccdShape>(m_models[i]);
    auto body = makeSceneRigidBody(m_scene, b, model, shape.get(), settings.allowSleeping);
    m_world->addRigidBody(body.get());
    m_bodies.push_back(body.get());
    m_bullet->shapes.push_back(std::move(shape));
    m_bullet->bodies.push_back(std::move(body));
  }

  // Thin static bodies, for the tunnelling check.
  for (std::size_t i = 0; i < m_scene.bodies.size(); ++i) {
    if (!m_scene.bodies[i].isStatic) continue;
    const Vec3 size = m_models[i]->boundsInBody().sizes();
    int axes[3] = {0, 1, 2};
    std::sort(axes, axes + 3, [&](int a, int b) { return size[a] < size[b]; });
    if (!(size[axes[0]] < 0.25 * size[axes[1]])) continue;
    const SceneBodyState s = bodyState(static_cast<int>(i));
    const Mat3 r = s.orientation.toRotationMatrix();
    Plate plate;
    plate.center = s.position + r * m_models[i]->boundsInBody().center();
    plate.normal = r.col(axes[0]);
    plate.axisU = r.col(axes[1]);
    plate.axisV = r.col(axes[2]);
    plate.halfU = 0.5 * size[axes[1]];
    plate.halfV = 0.5 * size[axes[2]];
    for (int j = 0; j < bodyCount(); ++j) {
      plate.startSide.push_back(plate.normal.dot(bodyState(j).position - plate.center) >= 0 ? 1 : -1);
    }
    m_plates.push_back(plate);
  }
}

SceneWorld::~SceneWorld() {
  m_contacts.reset();  // out of the world before the world goes
  m_bullet.reset();
}

void SceneWorld::step() {
  // State set on the bodies between steps (btRigidBody setters) is checked before Bullet integrates it: a
  // NaN or infinity would otherwise spread through contacts into other bodies and into the output.
  for (int i = 0; i < bodyCount(); ++i) {
    if (const char* what = nonFiniteState(*m_bodies[static_cast<std::size_t>(i)])) {
      throw Error("SceneWorld::step: body '" + bodyName(i) + "' (bodies[" + std::to_string(i) + "]) has a non-finite " +
                  what + " at frame " + std::to_string(m_frame));
    }
  }
  // Kinematic bodies move by their scene velocity; Bullet takes their velocity from the move.
  for (int i = 0; i < bodyCount(); ++i) {
    const SceneBody& b = m_scene.bodies[static_cast<std::size_t>(i)];
    if (!b.kinematic) continue;
    btRigidBody& body = *m_bodies[static_cast<std::size_t>(i)];
    btTransform next;
    btTransformUtil::integrateTransform(body.getWorldTransform(), toBt(b.velocity), toBt(b.angularVelocity),
                                        btScalar(m_scene.timestep), next);
    body.setWorldTransform(next);
  }
  const double ccdBefore = m_contacts->statistics().ccdSeconds;
  const auto start = std::chrono::steady_clock::now();
  m_world->stepSimulation(btScalar(m_scene.timestep), 0);
  const double stepSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++m_frame;
  m_last.time = time();
  m_last.contacts = m_contacts->lastStepContactCount();
  m_last.penetrationCells = m_contacts->lastStepMaxPenetrationCells();
  m_last.ccdSeconds = m_contacts->statistics().ccdSeconds - ccdBefore;
  m_last.stepSeconds = stepSeconds;
  m_last.clamps = m_contacts->lastStepClamps();
  m_maxPenetrationCells = std::max(m_maxPenetrationCells, m_last.penetrationCells);
  m_ccdSeconds += m_last.ccdSeconds;
  m_stepSeconds += stepSeconds;
  m_clamps += m_last.clamps;
}

SceneBodyState SceneWorld::bodyState(int i) const {
  const btRigidBody& b = *m_bodies[static_cast<std::size_t>(i)];
  SceneBodyState s;
  const btTransform& t = b.getWorldTransform();
  s.position = toVec3(t.getOrigin());
  const btQuaternion q = t.getRotation();
  s.orientation = Quat(q.w(), q.x(), q.y(), q.z());
  s.linearVelocity = toVec3(b.getLinearVelocity());
  s.angularVelocity = toVec3(b.getAngularVelocity());
  return s;
}

double SceneWorld::kineticEnergy() const {
  double energy = 0.0;
  for (int i = 0; i < bodyCount(); ++i) {
    const btRigidBody& b = *m_bodies[static_cast<std::size_t>(i)];
    if (isStatic(i) || !(b.getInvMass() > 0)) continue;  // static and kinematic bodies
    const double mass = 1.0 / double(b.getInvMass());
    const Vec3 v = toVec3(b.getLinearVelocity());
    const Vec3 wInBody = toVec3(b.getAngularVelocity() * b.getWorldTransform().getBasis());
    const Vec3 inertia = model(i).principalInertia(mass);
    energy += 0.5 * mass * v.squaredNorm() + 0.5 * wInBody.dot(inertia.cwiseProduct(wInBody));
  }
  return energy;
}

bool SceneWorld::hasNonFinite() const {
  for (int i = 0; i < bodyCount(); ++i) {
    const SceneBodyState s = bodyState(i);
    if (!s.position.allFinite() || !s.orientation.coeffs().allFinite() || !s.linearVelocity.allFinite() ||
        !s.angularVelocity.allFinite()) {
      return true;
    }
  }
  return false;
}

std::vector<std::string> SceneWorld::tunneledBodies() const {
  std::vector<std::string> out;
  for (int i = 0; i < bodyCount(); ++i) {
    if (isStatic(i)) continue;
    const Vec3 com = bodyState(i).position;
    bool tunneled = m_scene.has("ground") && com.y() < m_scene.groundHeight;
    for (const Plate& p : m_plates) {
      const Vec3 d = com - p.center;
      const int side = p.normal.dot(d) >= 0 ? 1 : -1;
      if (side != p.startSide[static_cast<std::size_t>(i)] && std::abs(p.axisU.dot(d)) <= p.halfU &&
          std::abs(p.axisV.dot(d)) <= p.halfV) {
        tunneled = true;
      }
    }
    if (tunneled) out.push_back(bodyName(i));
  }
  return out;
}

std::uint64_t SceneWorld::stateHash() const {
  std::string bytes;
  for (int i = 0; i < bodyCount(); ++i) {
    const btRigidBody& b = *m_bodies[static_cast<std::size_t>(i)];
    const btTransform& t = b.getWorldTransform();
    const btQuaternion q = t.getRotation();
    const btScalar values[13] = {t.getOrigin().x(),
                                 t.getOrigin().y(),
                                 t.getOrigin().z(),
                                 q.w(),
                                 q.x(),
                                 q.y(),
                                 q.z(),
                                 b.getLinearVelocity().x(),
                                 b.getLinearVelocity().y(),
                                 b.getLinearVelocity().z(),
                                 b.getAngularVelocity().x(),
                                 b.getAngularVelocity().y(),
                                 b.getAngularVelocity().z()};
    bytes.append(reinterpret_cast<const char*>(values), sizeof values);
  }
  return fnv1a(bytes);
}

}  // namespace sdfccd::bullet
