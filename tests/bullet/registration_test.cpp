// The dispatcher finds our algorithm for every pair involving SdfccdShape, in both orders, for contacts and
// closest points (compounds keep Bullet's compound algorithms, which dispatch their children back to ours), for as
// long as the ContactSystem that installed it lives.
#include <BulletCollision/CollisionDispatch/btCollisionDispatcherMt.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btEmptyCollisionAlgorithm.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolverMt.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorldMt.h>
#include <LinearMath/btThreads.h>
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "../../bullet_ext/src/algorithm/collision_algorithm.h"
#include "bullet_test_util.h"
#include "bullet_world_fixture.h"
#include "sdfccd/bullet/contact_system.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "sdfccd/error.h"
#include "sdfccd/mesh/procedural_meshes.h"

namespace sdfccd {
namespace {

std::shared_ptr<const BodyModel> smallSphereModel() {
  BodyModelSettings s;
  s.resolution = 16;
  s.points = 100;
  return BodyModel::buildFromMesh(makeIcosphere(0.1, 2), s);
}

enum class Found { Ours, Empty, Other, None };

Found find(btCollisionDispatcher& dispatcher, btCollisionShape* a, btCollisionShape* b, ebtDispatcherQueryType type) {
  btCollisionObject objectA, objectB;
  objectA.setCollisionShape(a);
  objectB.setCollisionShape(b);
  btCollisionObjectWrapper wrapA(nullptr, a, &objectA, objectA.getWorldTransform(), -1, -1);
  btCollisionObjectWrapper wrapB(nullptr, b, &objectB, objectB.getWorldTransform(), -1, -1);
  btCollisionAlgorithm* algorithm = dispatcher.findAlgorithm(&wrapA, &wrapB, nullptr, type);
  if (algorithm == nullptr) return Found::None;
  Found found = Found::Other;
  if (dynamic_cast<bullet::detail::CollisionAlgorithm*>(algorithm) != nullptr) found = Found::Ours;
  if (dynamic_cast<btEmptyAlgorithm*>(algorithm) != nullptr) found = Found::Empty;
  algorithm->~btCollisionAlgorithm();
  dispatcher.freeCollisionAlgorithm(algorithm);
  return found;
}

TEST(Registration, EveryPairInBothOrdersAndBothQueryTypes) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  const bullet::ContactSystem system(dispatcher);
  bullet::SdfccdShape ours(smallSphereModel());
  bullet::SdfccdShape other(smallSphereModel());
  btStaticPlaneShape plane(btVector3(0, 1, 0), 0);
  btBoxShape box(btVector3(1, 1, 1));
  btSphereShape sphere(1);
  btCylinderShape cylinder(btVector3(1, 1, 1));
  for (ebtDispatcherQueryType type : {BT_CONTACT_POINT_ALGORITHMS, BT_CLOSEST_POINT_ALGORITHMS}) {
    EXPECT_EQ(find(dispatcher, &ours, &other, type), Found::Ours);
    EXPECT_EQ(find(dispatcher, &ours, &plane, type), Found::Ours);
    EXPECT_EQ(find(dispatcher, &plane, &ours, type), Found::Ours);
    EXPECT_EQ(find(dispatcher, &ours, &box, type), Found::Ours);  // convex pairs: convex_pairs_test.cpp
    EXPECT_EQ(find(dispatcher, &sphere, &ours, type), Found::Ours);
    // Every other shape gets our algorithm too (other_shapes_test.cpp), never Bullet's cast to btSdfCollisionShape.
    EXPECT_EQ(find(dispatcher, &ours, &cylinder, type), Found::Ours);
    EXPECT_EQ(find(dispatcher, &cylinder, &ours, type), Found::Ours);
  }
  EXPECT_EQ(ours.getShapeType(), CUSTOM_CONCAVE_SHAPE_TYPE);
  EXPECT_TRUE(bullet::isSdfccdShape(&ours));
  EXPECT_FALSE(bullet::isSdfccdShape(&box));
}

// isSdfccdShape knows our shape by its name's address first, then by its characters: a shape of our type id is
// ours exactly when its name reads "SdfccdShape", wherever that text is stored.
TEST(Registration, OurShapeIsKnownByTypeAndNameWhereverTheNameLives) {
  bullet::SdfccdShape ours(smallSphereModel());
  EXPECT_STREQ(ours.getName(), "SdfccdShape");
  bullet::SdfccdShape other(smallSphereModel());
  EXPECT_EQ(ours.getName(), other.getName());  // one address for every instance (the fast path)
  const test::UserConcaveShape copyOfOurName(CUSTOM_CONCAVE_SHAPE_TYPE,
                                             std::string("Sdfccd") + "Shape");  // same text, other address
  ASSERT_NE(copyOfOurName.getName(), ours.getName());
  EXPECT_TRUE(bullet::isSdfccdShape(&copyOfOurName));
  EXPECT_FALSE(bullet::isSdfccdShape(static_cast<const btCollisionShape*>(nullptr)));
  for (const char* name : {"SdfccdShap", "SdfccdShape ", "sdfccdShape", "SDF", ""}) {
    const test::UserConcaveShape user(CUSTOM_CONCAVE_SHAPE_TYPE, name);
    EXPECT_FALSE(bullet::isSdfccdShape(&user)) << '"' << name << '"';
  }
}

// The contact system finds each body's motion of the step by its world array index first (a guess it checks against
// the object). Removing a body moves the world's last object into its index: here a box takes the index of a box
// that had contacts. It must move exactly as in a world where nothing is removed: each body's response is its own
// pairs' (with the guess taken unchecked its lookup returns the ground's motion: a pair of one body).
TEST(Registration, RemovingABodyMidRunLeavesTheOthersTheirOwnMotions) {
  BodyModelSettings model;
  model.resolution = 24;
  model.points = 200;
  const auto box = BodyModel::buildFromMesh(makeBox(Vec3(0.1, 0.05, 0.1)), model);
  struct Run {
    btTransform pose;
    btVector3 velocity, angularVelocity;
    Vec3 force = Vec3::Zero();  // on the box that stays, summed over the steps after the removal
    int pairsAfter = 0;         // pairs reported in the steps after the removal
    bool onlyTheBoxOnTheGround = true;
  };
  const auto run = [&box](bool remove) {
    bullet::ContactSettings settings;
    settings.mode = SdfccdContactMode::Penalty;  // the force on the box is its contact's, reported per step
    test::BulletTestWorld w{settings};
    // In this order the step meets the removed box first, then the ground, then the box that stays (Bullet's pairs
    // list the earlier added body first); after the removal the box that stays has index 0, whose guess is the
    // removed box's place, 0, and the ground, met first now, holds that place.
    btRigidBody& removed = w.add(std::make_unique<bullet::SdfccdShape>(box), 1.0, Vec3(-0.5, 0.06, 0.0));
    btRigidBody& ground =
        w.add(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), btScalar(0)), 0.0, Vec3::Zero());
    btRigidBody& stays = w.add(std::make_unique<bullet::SdfccdShape>(box), 1.0, Vec3(0.5, 0.06, 0.0));
    EXPECT_EQ(stays.getWorldArrayIndex(), 2);
    w.step(300, 0.001);
    EXPECT_EQ(w.contacts->lastStepContacts().size(), 2u);  // both boxes on the ground
    if (remove) {
      w.world.removeRigidBody(&removed);
      EXPECT_EQ(stays.getWorldArrayIndex(), 0);
    }
    Run r;
    for (int i = 0; i < 300; ++i) {
      w.step(1, 0.001);
      for (const bullet::PairContact& pair : w.contacts->lastStepContacts()) {
        ++r.pairsAfter;
        if (pair.shellObject != &stays) continue;
        r.onlyTheBoxOnTheGround = r.onlyTheBoxOnTheGround && pair.fieldObject == &ground;
        r.force += pair.forceOnShell;
      }
    }
    r.pose = stays.getCenterOfMassTransform();
    r.velocity = stays.getLinearVelocity();
    r.angularVelocity = stays.getAngularVelocity();
    if (remove) w.world.addRigidBody(&removed);  // the fixture removes every body it added
    return r;
  };
  const Run kept = run(false);
  const Run removed = run(true);
  EXPECT_EQ(kept.pairsAfter, 600);
  EXPECT_EQ(removed.pairsAfter, 300);  // the box that stays, on the ground, every step
  EXPECT_TRUE(removed.onlyTheBoxOnTheGround);
  EXPECT_EQ(removed.force, kept.force);
  EXPECT_NEAR(removed.force.y() / 300, 9.81, 0.2);  // its contact carries its weight m g
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(removed.pose.getOrigin()[k], kept.pose.getOrigin()[k]);
    EXPECT_EQ(removed.velocity[k], kept.velocity[k]);
    EXPECT_EQ(removed.angularVelocity[k], kept.angularVelocity[k]);
  }
  EXPECT_TRUE(removed.pose.getBasis() == kept.pose.getBasis());
}

// Bullet's convex shapes (beyond the paper): box, sphere and the three capsules, both orders, both query types.
TEST(Registration, ConvexShapesInBothOrders) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  const bullet::ContactSystem system(dispatcher);
  bullet::SdfccdShape ours(smallSphereModel());
  btBoxShape box(btVector3(1, 1, 1));
  btSphereShape sphere(1);
  btCapsuleShape capsuleY(0.5, 1);
  btCapsuleShapeX capsuleX(0.5, 1);
  btCapsuleShapeZ capsuleZ(0.5, 1);
  btCylinderShape cylinder(btVector3(1, 1, 1));
  btConeShape cone(1, 1);
  for (ebtDispatcherQueryType type : {BT_CONTACT_POINT_ALGORITHMS, BT_CLOSEST_POINT_ALGORITHMS}) {
    for (btCollisionShape* convex : std::vector<btCollisionShape*>{&box, &sphere, &capsuleY, &capsuleX, &capsuleZ}) {
      EXPECT_EQ(find(dispatcher, &ours, convex, type), Found::Ours) << convex->getName();
      EXPECT_EQ(find(dispatcher, convex, &ours, type), Found::Ours) << convex->getName();
    }
    // Any other convex shape: ours too, through its support points (other_shapes_test.cpp).
    EXPECT_EQ(find(dispatcher, &ours, &cylinder, type), Found::Ours);
    EXPECT_EQ(find(dispatcher, &cone, &ours, type), Found::Ours);
  }
}

TEST(Registration, ShapeMassPropertiesAndScaling) {
  auto model = smallSphereModel();
  bullet::SdfccdShape shape(model);
  btVector3 inertia;
  shape.calculateLocalInertia(2.0f, inertia);
  // A fine icosphere is close to a solid sphere: 2/5 m r^2 (the polyhedron is slightly smaller).
  EXPECT_NEAR(inertia.x(), 0.4 * 2.0 * 0.01, 0.05 * 0.4 * 2.0 * 0.01);
  EXPECT_NEAR(inertia.x(), inertia.y(), 1e-6);
  EXPECT_THROW(shape.setLocalScaling(btVector3(2, 2, 2)), Error);
  EXPECT_NO_THROW(shape.setLocalScaling(btVector3(1, 1, 1)));
  EXPECT_THROW(bullet::SdfccdShape(nullptr), Error);
}

// A ray cast reaches the mesh through processAllTriangles (the reason for a concave-range type id).
TEST(Registration, RayTestHitsTheMesh) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btCollisionWorld world(&dispatcher, &broadphase, &configuration);
  const bullet::ContactSystem system(world);
  bullet::SdfccdShape shape(smallSphereModel());
  btCollisionObject object;
  object.setCollisionShape(&shape);
  world.addCollisionObject(&object);
  btCollisionWorld::ClosestRayResultCallback ray(btVector3(0, 1, 0), btVector3(0, -1, 0));
  world.rayTest(btVector3(0, 1, 0), btVector3(0, -1, 0), ray);
  ASSERT_TRUE(ray.hasHit());
  EXPECT_NEAR(ray.m_hitPointWorld.y(), 0.1, 0.01);
  world.removeCollisionObject(&object);
}

// A sphere body dropped on a plane rests on it while the contact system lives; once it is gone, our pairs get no
// contact and the world still steps (its pairs' algorithms were freed with it: no use-after-free, run under ASan
// too).
TEST(Registration, DestroyingTheSystemTakesTheContactOut) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, -9.81f, 0));
  std::optional<bullet::ContactSystem> system(std::in_place, world);
  btStaticPlaneShape planeShape(btVector3(0, 1, 0), 0);
  btRigidBody ground(0, nullptr, &planeShape);
  world.addRigidBody(&ground);
  bullet::SdfccdShape shape(smallSphereModel());
  btVector3 inertia;
  shape.calculateLocalInertia(1, inertia);
  btRigidBody ball(1, nullptr, &shape, inertia);
  ball.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0.3f, 0)));
  world.addRigidBody(&ball);
  for (int i = 0; i < 240; ++i) world.stepSimulation(1.0f / 240, 0);
  // It rests on the plane: the sphere's radius above it, within a few cells of penetration.
  EXPECT_NEAR(ball.getWorldTransform().getOrigin().y(), 0.1, 0.01);
  system.reset();
  for (int i = 0; i < 60; ++i) world.stepSimulation(1.0f / 240, 0);
  EXPECT_LT(ball.getWorldTransform().getOrigin().y(), 0.05);  // it falls through the plane now
  world.removeRigidBody(&ball);
  world.removeRigidBody(&ground);
}

// A dispatcher takes one live contact system: a second one is refused while the first lives, and accepted once it
// is gone; it then serves the pairs the world already has.
TEST(Registration, OneLiveSystemPerDispatcher) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  std::optional<bullet::ContactSystem> first(std::in_place, world);
  test::expectOneLineError([&] { const bullet::ContactSystem second(world); }, "live ContactSystem");
  test::expectOneLineError([&] { const bullet::ContactSystem second(dispatcher); }, "live ContactSystem");
  btStaticPlaneShape planeShape(btVector3(0, 1, 0), 0);
  btRigidBody ground(0, nullptr, &planeShape);
  world.addRigidBody(&ground);
  bullet::SdfccdShape shape(smallSphereModel());
  btRigidBody ball(1, nullptr, &shape, btVector3(0.004f, 0.004f, 0.004f));
  ball.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0.1f, 0)));
  world.addRigidBody(&ball);
  for (int i = 0; i < 10; ++i) world.stepSimulation(1.0f / 240, 0);
  EXPECT_GT(first->statistics().ccdQueries, 0);
  first.reset();
  const bullet::ContactSystem second(world);  // with live pairs: their algorithms are made anew, ours
  for (int i = 0; i < 10; ++i) world.stepSimulation(1.0f / 240, 0);
  EXPECT_GT(second.statistics().ccdQueries, 0);
  EXPECT_NEAR(ball.getWorldTransform().getOrigin().y(), 0.1, 0.01);
  world.removeRigidBody(&ball);
  world.removeRigidBody(&ground);
}

// Our sphere as a compound's child resting on the bunny: Bullet's compound algorithm holds a child algorithm of
// ours. A contact system that goes must free it with the rest (else it keeps calling the system that went: a
// use-after-free, run under ASan), and the next system serves the child.
TEST(Registration, CompoundChildAlgorithmsGoWithTheSystem) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, -9.81f, 0));
  std::optional<bullet::ContactSystem> system(std::in_place, world);
  bullet::SdfccdShape bunnyShape(test::buildTestBunny(2000));
  btRigidBody bunny(0, nullptr, &bunnyShape);
  world.addRigidBody(&bunny);
  bullet::SdfccdShape child(smallSphereModel());
  btCompoundShape compound;
  compound.addChildShape(btTransform::getIdentity(), &child);
  btRigidBody ball(1, nullptr, &compound, btVector3(0.004f, 0.004f, 0.004f));
  ball.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0.35f, 0)));
  world.addRigidBody(&ball);
  for (int i = 0; i < 120; ++i) world.stepSimulation(1.0f / 240, 0);
  ASSERT_GT(system->statistics().ccdQueries, 0);  // the child pair met the bunny
  const btTransform resting = ball.getWorldTransform();
  auto putBack = [&] {  // on the bunny again (it falls through while no system is installed)
    ball.setWorldTransform(resting);
    ball.setLinearVelocity(btVector3(0, 0, 0));
    ball.setAngularVelocity(btVector3(0, 0, 0));
  };
  system.reset();
  for (int i = 0; i < 5; ++i) world.stepSimulation(1.0f / 240, 0);
  putBack();
  system.emplace(world);
  for (int i = 0; i < 10; ++i) world.stepSimulation(1.0f / 240, 0);
  EXPECT_GT(system->statistics().ccdQueries, 0);
  system.reset();
  world.removeRigidBody(&ball);
  world.removeRigidBody(&bunny);
}

// Bullet's multi-threaded world and dispatcher are refused with a clear error.
TEST(Registration, MultiThreadedWorldIsRefused) {
  // Bullet's Mt classes need a task scheduler to be constructed; the sequential one, restored afterwards.
  btITaskScheduler* const previousScheduler = btGetTaskScheduler();
  btSetTaskScheduler(btGetSequentialTaskScheduler());
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcherMt dispatcherMt(&configuration);
  EXPECT_THROW(bullet::ContactSystem{dispatcherMt}, Error);
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btConstraintSolverPoolMt pool(1);
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorldMt world(&dispatcher, &broadphase, &pool, &solver, &configuration);
  try {
    const bullet::ContactSystem system(world);
    ADD_FAILURE() << "btDiscreteDynamicsWorldMt was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("btDiscreteDynamicsWorldMt"), std::string::npos) << e.what();
  }
  btSetTaskScheduler(previousScheduler);
}

}  // namespace
}  // namespace sdfccd
