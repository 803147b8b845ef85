// Bodies dropped on the ground come to rest at the analytic height: the contact height minus the
// penetration where the penalty forces carry the weight (Section 4.1), within a fraction of a cell.
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <cmath>

#include "bullet_test_util.h"
#include "sdfccd/bullet/scene_world.h"

namespace sdfccd {
namespace {

// Box: half extents (0.1, 0.05, 0.1), mass 1, k per point. The bottom face holds a share of the shell's
// points equal to its share of the area; each pushes k d straight up: d = m g / (k n_bottom).
TEST(Drop, BoxRestsAtAnalyticHeight) {
  const Scene scene = test::sceneFromText(R"({
    "timestep": 0.001, "frames": 700, "gravity": [0, -9.81, 0],
    "effects": ["gravity", "ground", "damping", "rotation"],
    "contact": { "mode": "penalty", "model": "continuous", "stiffness": 2000.0, "damping": 4.0 },
    "bodies": [ { "name": "box", "primitive": { "type": "box", "half_extents": [0.1, 0.05, 0.1] },
                  "mass": 1.0, "position": [0, 0.07, 0], "points": 400, "resolution": 24 } ] })");
  bullet::SceneWorld world(scene);
  for (int f = 0; f < scene.frames; ++f) world.step();
  const BodyModel& model = world.model(0);
  int bottom = 0;
  for (const Vec3& n : model.shell().normals) bottom += n.y() < -0.999 ? 1 : 0;
  ASSERT_GT(bottom, 50);
  const double depth = 9.81 / (2000.0 * bottom);
  const double expected = 0.05 - depth;
  const bullet::SceneBodyState s = world.bodyState(0);
  EXPECT_NEAR(s.position.y(), expected, 0.1 * model.cellSize()) << "cell " << model.cellSize();
  EXPECT_LT(s.linearVelocity.norm(), 0.02);
  EXPECT_TRUE(world.tunneledBodies().empty());
  EXPECT_FALSE(world.hasNonFinite());
  EXPECT_GT(world.contacts().lastStepContacts().size() + (world.body(0).isActive() ? 0u : 1u), 0u);
}

// Sphere of radius r with N points spread evenly: the points below the ground form a cap of depth d; their
// forces sum to k N d^2 / (4 r) (area density N / (4 pi r^2), cap ring area 2 pi r dh). Rest at r - d with
// d = sqrt(4 r m g / (k N)).
TEST(Drop, SphereRestsAtAnalyticHeight) {
  const Scene scene = test::sceneFromText(R"({
    "timestep": 0.001, "frames": 800, "gravity": [0, -9.81, 0],
    "effects": ["gravity", "ground", "damping"],
    "contact": { "mode": "penalty", "model": "continuous", "stiffness": 2000.0, "damping": 1.0 },
    "bodies": [ { "name": "ball", "primitive": { "type": "sphere", "radius": 0.1, "subdivisions": 4 },
                  "mass": 1.0, "position": [0, 0.13, 0], "points": 1500, "resolution": 24 } ] })");
  bullet::SceneWorld world(scene);
  for (int f = 0; f < scene.frames; ++f) {
    world.step();
    if (getenv("DBG") && f % 10 == 0)
      printf("%d y %.5f vy %.4f contacts %d pen %.3f clamps %d\n", f, world.bodyState(0).position.y(),
             world.bodyState(0).linearVelocity.y(), world.lastFrame().contacts, world.lastFrame().penetrationCells,
             world.lastFrame().clamps);
  }
  const double r = 0.1;
  const double n = static_cast<double>(world.model(0).shell().size());
  const double depth = std::sqrt(4 * r * 9.81 / (2000.0 * n));
  const bullet::SceneBodyState s = world.bodyState(0);
  EXPECT_NEAR(s.position.y(), r - depth, 0.1 * world.model(0).cellSize()) << "depth " << depth;
  EXPECT_NEAR(s.position.x(), 0.0, 0.02);  // no friction: uneven point normals let it slide a little
  EXPECT_LT(s.linearVelocity.norm(), 0.02);
}

// Manifold points are visible to users, and the solver does not respond to them (processing threshold).
TEST(Drop, ContactsAreReportedButNotSolvedTwice) {
  const Scene scene = test::sceneFromText(R"({
    "timestep": 0.001, "frames": 300, "effects": ["gravity", "ground", "damping"],
    "contact": { "mode": "penalty", "stiffness": 2000.0, "damping": 4.0 },
    "bodies": [ { "primitive": { "type": "box", "half_extents": [0.1, 0.05, 0.1] }, "mass": 1.0,
                  "position": [0, 0.05, 0], "points": 300, "resolution": 16 } ] })");
  bullet::SceneWorld world(scene);
  for (int f = 0; f < 50; ++f) world.step();
  btDispatcher* dispatcher = world.world().getDispatcher();
  int points = 0;
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(m);
    points += manifold->getNumContacts();
    EXPECT_LT(manifold->getContactProcessingThreshold(), -1e10);
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      EXPECT_LT(manifold->getContactPoint(p).getDistance(), 0.0f);
      EXPECT_GT(std::abs(manifold->getContactPoint(p).m_normalWorldOnB.y()), 0.9f);
    }
  }
  EXPECT_GT(points, 0);
  EXPECT_GT(world.lastFrame().contacts, 0);
}

}  // namespace
}  // namespace sdfccd

namespace sdfccd {
namespace {

// A body at rest falls asleep (Bullet's thresholds); another one landing on it wakes it.
TEST(Drop, SleepingBodyWakesOnContact) {
  const Scene scene = test::sceneFromText(R"({
    "timestep": 0.001, "frames": 3000, "effects": ["gravity", "ground", "damping"],
    "contact": { "mode": "penalty", "stiffness": 2000.0, "damping": 4.0 },
    "bodies": [
      { "name": "bottom", "primitive": { "type": "box", "half_extents": [0.1, 0.05, 0.1] }, "mass": 1.0,
        "position": [0, 0.0499, 0], "points": 300, "resolution": 16 },
      { "name": "top", "primitive": { "type": "box", "half_extents": [0.05, 0.05, 0.05] }, "mass": 1.0,
        "position": [0, 5.0, 0], "points": 200, "resolution": 16 } ] })");
  bullet::SceneWorld world(scene);
  // Bullet's global time a body must stay slow before it sleeps (default 2 s); shortened for the test.
  struct DeactivationTimeGuard {
    btScalar saved = gDeactivationTime;
    ~DeactivationTimeGuard() { gDeactivationTime = saved; }
  } guard;
  gDeactivationTime = btScalar(0.3);
  // Keep the falling box out of the way until the bottom one sleeps: it starts 5 m up (about 1 s of fall).
  bool slept = false;
  int frame = 0;
  for (; frame < 3000 && !slept; ++frame) {
    world.step();
    slept = world.body(0).getActivationState() == ISLAND_SLEEPING;
  }
  ASSERT_TRUE(slept) << "the bottom box never slept";
  ASSERT_GT(world.bodyState(1).position.y(), 0.3) << "the top box arrived before the bottom one slept";
  bool woke = false;
  for (; frame < 3000 && !woke; ++frame) {
    world.step();
    woke = world.body(0).isActive();
  }
  EXPECT_TRUE(woke);
  for (int f = 0; f < 300; ++f) world.step();
  EXPECT_TRUE(world.tunneledBodies().empty());
  EXPECT_GT(world.bodyState(1).position.y(), 0.1);  // the top box rests on the bottom one
}

}  // namespace
}  // namespace sdfccd
