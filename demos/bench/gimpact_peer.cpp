/// @file
/// @brief GImpactPeer (see gimpact_peer.h).
#if __has_include("sdfccd/bullet/scene_world.h")  // built only with the Bullet plugin
#include "bench/gimpact_peer.h"

#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <LinearMath/btConvexHullComputer.h>
#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <map>

#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/error.h"

namespace sdfccd::cli {

/// One mesh in Bullet's single precision and Bullet's shape over it (shared by the bodies of one model): the
/// GImpact shape over the triangles, or a convex hull / box (then the arrays stay empty).
struct GImpactPeerMesh {
  std::vector<btScalar> vertices;
  std::vector<int> indices;
  std::unique_ptr<btTriangleIndexVertexArray> array;
  std::unique_ptr<btCollisionShape> shape;
};

/// Bullet's objects, destroyed in the right order.
struct GImpactPeerBullet {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
  std::map<const BodyModel*, std::unique_ptr<GImpactPeerMesh>> meshes;
  std::unique_ptr<btStaticPlaneShape> groundShape;
  std::vector<std::unique_ptr<btRigidBody>> statics;
  std::vector<std::unique_ptr<btRigidBody>> bodies;  // one per scene body, in scene order
  ~GImpactPeerBullet() {
    for (auto& b : bodies) world.removeRigidBody(b.get());
    for (auto& b : statics) world.removeRigidBody(b.get());
  }
};

namespace {

btVector3 toBt(const Vec3& v) {
  return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z()));
}

std::unique_ptr<GImpactPeerMesh> makeMesh(const TriangleMesh& meshInBody) {
  auto mesh = std::make_unique<GImpactPeerMesh>();
  for (const Vec3& v : meshInBody.vertices) {
    for (int k = 0; k < 3; ++k) mesh->vertices.push_back(btScalar(v[k]));
  }
  for (const auto& t : meshInBody.triangles) mesh->indices.insert(mesh->indices.end(), t.begin(), t.end());
  mesh->array = std::make_unique<btTriangleIndexVertexArray>(
      static_cast<int>(meshInBody.triangles.size()), mesh->indices.data(), static_cast<int>(3 * sizeof(int)),
      static_cast<int>(meshInBody.vertices.size()), mesh->vertices.data(), static_cast<int>(3 * sizeof(btScalar)));
  auto shape = std::make_unique<btGImpactMeshShape>(mesh->array.get());
  shape->updateBound();  // GImpact needs its bounding volumes built before the first step
  mesh->shape = std::move(shape);
  return mesh;
}

// Bullet's convex fast path for one body: a btBoxShape of the mesh's extent for a box primitive (exact: the box
// mesh is centred), else a btConvexHullShape of the mesh's hull vertices (the hull computed once, not per step).
std::unique_ptr<GImpactPeerMesh> makeConvex(const TriangleMesh& meshInBody, bool isBox) {
  auto mesh = std::make_unique<GImpactPeerMesh>();
  if (isBox) {
    Vec3 half = Vec3::Zero();
    for (const Vec3& v : meshInBody.vertices) half = half.cwiseMax(v.cwiseAbs());
    mesh->shape = std::make_unique<btBoxShape>(toBt(half));
    return mesh;
  }
  std::vector<double> coords;
  for (const Vec3& v : meshInBody.vertices) coords.insert(coords.end(), {v.x(), v.y(), v.z()});
  btConvexHullComputer hull;
  hull.compute(coords.data(), int(3 * sizeof(double)), int(meshInBody.vertices.size()), 0.0, 0.0);
  auto shape = std::make_unique<btConvexHullShape>();
  for (int i = 0; i < hull.vertices.size(); ++i) shape->addPoint(hull.vertices[i], false);
  shape->recalcLocalAabb();
  mesh->shape = std::move(shape);
  return mesh;
}

}  // namespace

GImpactPeer::GImpactPeer(const Scene& scene, const std::vector<std::shared_ptr<const BodyModel>>& models,
                         PeerShape shapeKind, double timestep)
    : m_bullet(std::make_unique<GImpactPeerBullet>()), m_timestep(timestep > 0.0 ? timestep : scene.timestep) {
  if (models.size() != scene.bodies.size()) throw Error("GImpactPeer: one model per scene body is needed");
  btGImpactCollisionAlgorithm::registerAlgorithm(&m_bullet->dispatcher);
  btDiscreteDynamicsWorld& world = m_bullet->world;
  world.setGravity(scene.has("gravity") ? toBt(scene.gravity) : btVector3(0, 0, 0));
  if (scene.has("ground")) {
    m_bullet->groundShape = std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), btScalar(scene.groundHeight));
    btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, m_bullet->groundShape.get());
    m_bullet->statics.push_back(std::make_unique<btRigidBody>(info));
    world.addRigidBody(m_bullet->statics.back().get());
  }
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const SceneBody& b = scene.bodies[i];
    const BodyModel& model = *models[i];
    auto& mesh = m_bullet->meshes[&model];
    const bool isBox = b.primitive && b.primitive->type == "box";
    if (!mesh)
      mesh = shapeKind == PeerShape::GImpact ? makeMesh(model.meshInBody()) : makeConvex(model.meshInBody(), isBox);
    auto body = bullet::makeSceneRigidBody(scene, b, model, mesh->shape.get(), true);  // sleeping as the scene says
    world.addRigidBody(body.get());
    m_bullet->bodies.push_back(std::move(body));
  }
}

GImpactPeer::~GImpactPeer() = default;

void GImpactPeer::step() {
  m_bullet->world.stepSimulation(btScalar(m_timestep), 0);
}

int GImpactPeer::bodyCount() const {
  return static_cast<int>(m_bullet->bodies.size());
}

Rigid GImpactPeer::worldFromBody(int i) const {
  const btTransform& t = m_bullet->bodies[static_cast<std::size_t>(i)]->getWorldTransform();
  const btQuaternion q = t.getRotation();
  Rigid r = Rigid::Identity();
  r.linear() = Quat(q.w(), q.x(), q.y(), q.z()).normalized().toRotationMatrix();
  r.translation() = Vec3(t.getOrigin().x(), t.getOrigin().y(), t.getOrigin().z());
  return r;
}

double GImpactPeer::margin() const {
  if (m_bullet->meshes.empty()) return 0.0;
  const btCollisionShape& any = *m_bullet->meshes.begin()->second->shape;
  const auto* gimpact = dynamic_cast<const btGImpactMeshShape*>(&any);
  if (gimpact && gimpact->getMeshPartCount() > 0) return double(gimpact->getMeshPart(0)->getMargin());
  return double(any.getMargin());
}

int GImpactPeer::hullVertices() const {
  if (m_bullet->meshes.empty()) return 0;
  const auto* hull = dynamic_cast<const btConvexHullShape*>(m_bullet->meshes.begin()->second->shape.get());
  return hull ? hull->getNumPoints() : 0;
}

double GImpactPeer::kineticEnergy() const {
  double energy = 0.0;
  for (const auto& b : m_bullet->bodies) {
    if (!(b->getInvMass() > 0)) continue;
    const btVector3 w = b->getAngularVelocity() * b->getWorldTransform().getBasis();  // in the body frame
    const btVector3& invInertia = b->getInvInertiaDiagLocal();
    double rotational = 0.0;
    for (int k = 0; k < 3; ++k) {
      if (invInertia[k] > 0) rotational += double(w[k]) * double(w[k]) / double(invInertia[k]);
    }
    energy += 0.5 * double(b->getLinearVelocity().length2()) / double(b->getInvMass()) + 0.5 * rotational;
  }
  return energy;
}

bool GImpactPeer::hasNonFinite() const {
  for (const auto& b : m_bullet->bodies) {
    const btTransform& t = b->getWorldTransform();
    const btVector3 v[4] = {t.getOrigin(), b->getLinearVelocity(), b->getAngularVelocity(),
                            btVector3(t.getRotation().x(), t.getRotation().y(), t.getRotation().z())};
    for (const btVector3& x : v) {
      if (!std::isfinite(x.x()) || !std::isfinite(x.y()) || !std::isfinite(x.z())) return true;
    }
  }
  return false;
}

int GImpactPeer::solverIterations() const {
  return m_bullet->world.getSolverInfo().m_numIterations;
}

}  // namespace sdfccd::cli

#endif
