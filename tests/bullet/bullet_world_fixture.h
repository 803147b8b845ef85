// A small dynamics world with our contact installed, owning its shapes and bodies: the fixture of
// the suites that drop bodies on Bullet's own shapes (convex_pairs_test.cpp, other_shapes_test.cpp).
#pragma once

#include <btBulletDynamicsCommon.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sdfccd/bullet/bullet_pose.h"
#include "sdfccd/bullet/contact_system.h"

namespace sdfccd::test {

/// A user's concave shape we know nothing about: of type `shapeType`, named `name` (owned: any text at any
/// address), a box of half-width 1 around its origin, no triangles.
class UserConcaveShape : public btConcaveShape {
 public:
  UserConcaveShape(int shapeType, std::string name) : m_name(std::move(name)) { m_shapeType = shapeType; }
  void getAabb(const btTransform& t, btVector3& aabbMin, btVector3& aabbMax) const override {
    aabbMin = t.getOrigin() - btVector3(1, 1, 1);
    aabbMax = t.getOrigin() + btVector3(1, 1, 1);
  }
  void processAllTriangles(btTriangleCallback*, const btVector3&, const btVector3&) const override {}
  void setLocalScaling(const btVector3& scaling) override { m_scaling = scaling; }
  const btVector3& getLocalScaling() const override { return m_scaling; }
  void calculateLocalInertia(btScalar, btVector3& inertia) const override { inertia.setValue(0, 0, 0); }
  const char* getName() const override { return m_name.c_str(); }

 private:
  std::string m_name;
  btVector3 m_scaling{1, 1, 1};
};

struct BulletTestWorld {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
  std::unique_ptr<bullet::ContactSystem> contacts;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> bodies;

  explicit BulletTestWorld(const bullet::ContactSettings& settings) {
    world.setGravity(btVector3(0, btScalar(-9.81), 0));
    contacts = std::make_unique<bullet::ContactSystem>(world, settings);
  }
  ~BulletTestWorld() {
    for (auto& b : bodies) world.removeRigidBody(b.get());
    contacts.reset();
  }
  BulletTestWorld(const BulletTestWorld&) = delete;
  BulletTestWorld& operator=(const BulletTestWorld&) = delete;

  /// A body of `shape` at `position` (no rotation), static when `mass` is 0, never deactivated otherwise.
  btRigidBody& add(std::unique_ptr<btCollisionShape> shape, double mass, const Vec3& position) {
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(btScalar(mass), inertia);
    btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), nullptr, shape.get(), inertia);
    info.m_startWorldTransform.setIdentity();
    info.m_startWorldTransform.setOrigin(bullet::toBtVector3(position));
    bodies.push_back(std::make_unique<btRigidBody>(info));
    if (mass > 0) bodies.back()->setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(bodies.back().get());
    shapes.push_back(std::move(shape));
    return *bodies.back();
  }
  /// `steps` fixed steps of `dt` seconds (no substeps).
  void step(int steps, double dt) {
    for (int i = 0; i < steps; ++i) world.stepSimulation(btScalar(dt), 0);
  }
};

}  // namespace sdfccd::test
