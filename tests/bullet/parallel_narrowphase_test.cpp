// The parallel narrowphase and resting pairs (resting_pairs.h). The pairs' CCD runs on a pool; Bullet
// sees the results serially in its pair order, so a run must end in the very same state for any thread count.
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "../../bullet_ext/src/shapes/bullet_shape_fields.h"
#include "../../bullet_ext/src/parallel/deferred_queries.h"
#include "../../bullet_ext/src/parallel/narrowphase_pool.h"
#include "bullet_test_util.h"
#include "sdfccd/bullet/scene_world.h"

namespace sdfccd {
namespace {

/// The state hash of the shipped 20-bunny drop after `frames` frames on `threads` narrowphase threads, and how
/// many of its CCD queries ran in the parallel batch.
struct ParallelRun {
  std::uint64_t hash = 0;
  std::int64_t queries = 0;
  std::int64_t deferred = 0;
};

ParallelRun runBunnyDrop(int threads, int frames, SdfccdContactMode mode) {
  Scene scene = loadScene(std::string(SDFCCD_ASSETS_DIR) + "/scenes/drop-bunnies.json");
  scene.contact.mode = mode;
  bullet::SceneWorldSettings settings;
  settings.narrowphaseThreads = threads;
  settings.cacheDir = "textbook-model-cache";  // the bunny's field and shell, built once for the suites
  bullet::SceneWorld world(scene, settings);
  for (int f = 0; f < frames; ++f) world.step();
  return {world.stateHash(), world.contacts().statistics().ccdQueries, world.contacts().statistics().deferredQueries};
}

// The golden drop (tests/bullet/golden_hash_test.cpp: 600 frames, its recorded hash; that test runs on the default
// thread count) on 1, 2 and 4 threads: the very same state, and most queries ran in the planned batch.
constexpr std::uint64_t kGoldenDropHash = 0xe4178163e11a2192ull;

TEST(ParallelNarrowphase, GoldenDropIdenticalFor1To4Threads) {
  for (int threads : {1, 2, 4}) {
    const ParallelRun run = runBunnyDrop(threads, 600, SdfccdContactMode::Penalty);
    EXPECT_EQ(run.hash, kGoldenDropHash) << threads << " threads";
    EXPECT_GT(run.deferred, run.queries / 2) << threads << " threads: most queries should run in the planned batch";
  }
}

TEST(ParallelNarrowphase, SolverDropIdenticalFor1And2Threads) {
  const ParallelRun one = runBunnyDrop(1, 300, SdfccdContactMode::Solver);
  const ParallelRun two = runBunnyDrop(2, 300, SdfccdContactMode::Solver);
  EXPECT_GT(one.deferred, one.queries / 2);
  EXPECT_EQ(two.hash, one.hash);
  EXPECT_EQ(two.queries, one.queries);
}

/// The ground plane's body of a SceneWorld.
btCollisionObject* groundOf(bullet::SceneWorld& world) {
  btCollisionObjectArray& objects = world.world().getCollisionObjectArray();
  for (int i = 0; i < objects.size(); ++i) {
    if (objects[i]->getCollisionShape()->getShapeType() == STATIC_PLANE_PROXYTYPE) return objects[i];
  }
  return nullptr;
}

// A pile gone to sleep runs no CCD, also when its ground is an active static body (Bullet dispatches those pairs)
// — and wakes as Bullet expects when a body lands on it.
TEST(ParallelNarrowphase, SleepingPileRunsNoCcd) {
  const Scene scene = test::sceneFromText(R"({
    "timestep": 0.001, "frames": 3000, "effects": ["gravity", "ground", "damping"],
    "contact": { "mode": "penalty", "stiffness": 2000.0, "damping": 4.0 },
    "bodies": [
      { "name": "bottom", "primitive": { "type": "box", "half_extents": [0.1, 0.05, 0.1] }, "mass": 1.0,
        "position": [0, 0.0499, 0], "points": 300, "resolution": 16 },
      { "name": "middle", "primitive": { "type": "box", "half_extents": [0.05, 0.05, 0.05] }, "mass": 1.0,
        "position": [0, 0.1498, 0], "points": 200, "resolution": 16 },
      { "name": "falling", "primitive": { "type": "box", "half_extents": [0.05, 0.05, 0.05] }, "mass": 1.0,
        "position": [0, 3.0, 0], "points": 200, "resolution": 16 } ] })");
  bullet::SceneWorld world(scene);
  btCollisionObject* ground = groundOf(world);
  ASSERT_NE(ground, nullptr);
  ground->setActivationState(DISABLE_DEACTIVATION);   // Bullet now dispatches every pair with the ground
  world.body(2).setActivationState(ISLAND_SLEEPING);  // held up there, asleep, until the pile sleeps too
  for (int f = 0; f < 200; ++f) world.step();
  const bullet::ContactStatistics& stats = world.contacts().statistics();
  // Awake, the two resting boxes run their CCD every step: each against the ground (one role each; the plane's
  // box is infinite, so the middle box's pair exists too) and bottom-middle (two roles).
  std::int64_t before = stats.ccdQueries;
  world.step();
  EXPECT_EQ(stats.ccdQueries - before, 4);
  // The pile goes to sleep the way Bullet's island manager puts it there (sleeping itself is tested by the textbook
  // suites).
  for (int i : {0, 1}) {
    world.body(i).setLinearVelocity(btVector3(0, 0, 0));
    world.body(i).setAngularVelocity(btVector3(0, 0, 0));
    world.body(i).setActivationState(ISLAND_SLEEPING);
  }
  const std::int64_t restingBefore = stats.restingPairs;
  std::vector<std::int64_t> perStep;
  for (int f = 0; f < 100; ++f) {
    before = stats.ccdQueries;
    world.step();
    perStep.push_back(stats.ccdQueries - before);
  }
  ASSERT_FALSE(perStep.empty());
  for (std::size_t f = 0; f < perStep.size(); ++f) EXPECT_EQ(perStep[f], 0) << "step " << f << " after sleeping";
  // Bullet dispatches the three ground pairs (the ground is active); they stop in our resting-pair check.
  EXPECT_EQ(stats.restingPairs - restingBefore, 3 * static_cast<std::int64_t>(perStep.size()));
  EXPECT_EQ(world.body(0).getActivationState(), ISLAND_SLEEPING);
  EXPECT_EQ(world.body(1).getActivationState(), ISLAND_SLEEPING);
  // The third box falls onto the pile: the pile wakes and its pairs run again.
  world.body(2).activate(true);
  for (int f = 0; f < 1500 && !world.body(1).isActive(); ++f) world.step();
  EXPECT_TRUE(world.body(1).isActive());
  before = stats.ccdQueries;
  world.step();
  EXPECT_GT(stats.ccdQueries - before, 0);
}

}  // namespace
}  // namespace sdfccd

// The pool, the deferred queries and the convex-shape cache directly (private headers of sdfccd::bullet).

namespace sdfccd {
namespace {

// Every index of every batch runs exactly once, whatever the thread count and batch size (empty batches too).
TEST(NarrowphasePool, EveryIndexOnceForManyBatches) {
  for (int threads : {1, 2, 4}) {
    bullet::detail::NarrowphasePool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    std::vector<std::atomic<int>> hits(64);
    int expected[64] = {};
    for (int batch = 0; batch < 300; ++batch) {
      const std::size_t count = static_cast<std::size_t>(batch % 65);
      pool.run(count, [&](std::size_t i) { hits[i].fetch_add(1); });
      for (std::size_t i = 0; i < count; ++i) ++expected[i];
    }
    for (std::size_t i = 0; i < hits.size(); ++i)
      EXPECT_EQ(hits[i].load(), expected[i]) << threads << " threads, " << i;
  }
}

// A query that throws on a worker is rethrown where its result is taken; a result is taken once; unknown keys
// have none.
TEST(DeferredQueries, ResultsTakenOnceAndErrorsRethrown) {
  bullet::detail::NarrowphasePool pool(2);
  bullet::detail::DeferredQueries queries;
  int manifolds[3];
  queries.add(&manifolds[0], 0, [](bullet::detail::RoleResult& out) { out.query.ccdSeconds = 1.5; });
  queries.add(&manifolds[0], 1, [](bullet::detail::RoleResult& out) { out.query.ccdSeconds = 2.5; });
  queries.add(&manifolds[1], 0, [](bullet::detail::RoleResult&) { throw std::runtime_error("query failed"); });
  EXPECT_EQ(queries.size(), 3u);
  EXPECT_EQ(queries.take(&manifolds[0], 0), nullptr) << "not computed yet";
  queries.runAll(pool);
  const bullet::detail::RoleResult* second = queries.take(&manifolds[0], 1);
  ASSERT_NE(second, nullptr);
  EXPECT_EQ(second->query.ccdSeconds, 2.5);
  const bullet::detail::RoleResult* first = queries.take(&manifolds[0], 0);
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->query.ccdSeconds, 1.5);
  EXPECT_EQ(queries.take(&manifolds[0], 0), nullptr) << "taken twice";
  EXPECT_EQ(queries.take(&manifolds[2], 0), nullptr) << "never planned";
  EXPECT_THROW(queries.take(&manifolds[1], 0), std::runtime_error);
  queries.clear();
  EXPECT_EQ(queries.size(), 0u);
}

// A streamed batch: tasks published in groups while the caller goes on writing the next ones' inputs; every task
// runs once and reads what was written before it was published (TSan checks the hand-over in the CI).
TEST(NarrowphasePool, StreamedBatchRunsEveryPublishedTaskOnceAfterItsInput) {
  for (int threads : {1, 2, 4}) {
    bullet::detail::NarrowphasePool pool(threads);
    for (int batch = 0; batch < 50; ++batch) {
      const std::size_t total = static_cast<std::size_t>(37 * batch % 101);
      std::vector<std::size_t> input(total, 0);
      std::vector<std::atomic<int>> runs(total);
      std::vector<std::size_t> output(total, 0);
      const std::function<void(std::size_t)> task = [&](std::size_t i) {
        runs[i].fetch_add(1);
        output[i] = 3 * input[i];
      };
      pool.begin(task);
      for (std::size_t i = 0; i < total; ++i) {
        input[i] = i + 1;  // written before the task is published
        if ((i + 1) % 5 == 0) pool.publish(i + 1);
      }
      pool.close(total);
      for (std::size_t i = 0; i < total; ++i) {
        ASSERT_EQ(runs[i].load(), 1) << threads << " threads, batch " << batch << ", task " << i;
        ASSERT_EQ(output[i], 3 * (i + 1)) << threads << " threads, batch " << batch << ", task " << i;
      }
    }
  }
}

// The workers claim from the front, the caller (once it closes the batch) from the back: with one worker, the
// worker's tasks are a prefix of the batch and the caller's the rest, every batch (so a task tends to stay on one
// core from step to step). Tasks take a few microseconds, so that both threads get some.
TEST(NarrowphasePool, WorkersClaimTheFrontAndTheCallerTheBack) {
  bullet::detail::NarrowphasePool pool(2);
  const std::thread::id caller = std::this_thread::get_id();
  int callerRan = 0;
  int workerRan = 0;
  for (int batch = 0; batch < 200; ++batch) {
    const std::size_t total = 40 + static_cast<std::size_t>(batch % 25);
    std::vector<char> byCaller(total, 0);
    std::vector<std::atomic<int>> runs(total);
    const std::function<void(std::size_t)> task = [&](std::size_t i) {
      runs[i].fetch_add(1);
      byCaller[i] = std::this_thread::get_id() == caller ? 1 : 0;
      const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(5);
      while (std::chrono::steady_clock::now() < until) {
      }
    };
    pool.begin(task);
    pool.publish(total / 4);  // the worker may start on these while the caller "plans" the rest
    pool.close(total);
    std::size_t firstByCaller = total;
    for (std::size_t i = 0; i < total; ++i) {
      ASSERT_EQ(runs[i].load(), 1) << "batch " << batch << ", task " << i;
      if (byCaller[i] && firstByCaller == total) firstByCaller = i;
      if (firstByCaller < total) {
        ASSERT_EQ(byCaller[i], 1) << "batch " << batch << ": the worker ran task " << i << " after the caller's "
                                  << firstByCaller;
      }
      (byCaller[i] ? callerRan : workerRan) += 1;
    }
  }
  EXPECT_GT(callerRan, 0);
  EXPECT_GT(workerRan, 0);
}

// A streamed DeferredQueries batch computes what was added, refuses more than its capacity (the role is then
// computed when Bullet reaches it), and keeps stashed inputs for the step.
TEST(DeferredQueries, StreamedBatchHonoursItsCapacityAndKeepsStashedInputs) {
  bullet::detail::NarrowphasePool pool(2);
  bullet::detail::DeferredQueries queries;
  int manifolds[12];
  for (int step = 0; step < 3; ++step) {
    queries.clear();
    queries.begin(pool, 10);
    for (int m = 0; m < 12; ++m) {
      const double& kept = queries.stash(double(100 * step + m));
      const bool added =
          queries.add(&manifolds[m], 0, [&kept](bullet::detail::RoleResult& out) { out.query.ccdSeconds = kept; });
      EXPECT_EQ(added, m < 10) << "query " << m;
    }
    queries.finish();
    for (int m = 0; m < 12; ++m) {
      const bullet::detail::RoleResult* result = queries.take(&manifolds[m], 0);
      if (m >= 10) {
        EXPECT_EQ(result, nullptr);
        continue;
      }
      ASSERT_NE(result, nullptr);
      EXPECT_EQ(result->query.ccdSeconds, double(100 * step + m));
    }
  }
}

// The convex cache serves a shape by its address while it is unchanged, builds anew when it changes, and drops
// what no pair used for the idle steps.
TEST(ConvexShapeCache, AddressLookupFollowsChangesAndEvictsIdleEntries) {
  btConvexHullShape hull;
  for (int corner = 0; corner < 8; ++corner) {
    hull.addPoint(btVector3(corner & 1 ? 0.1f : -0.1f, corner & 2 ? 0.2f : -0.2f, corner & 4 ? 0.3f : -0.3f));
  }
  bullet::detail::ConvexShapeCache cache;
  cache.evictIdle(0, 10);
  const ConvexPolytopeField* first = cache.field(&hull);
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(cache.field(&hull), first);
  EXPECT_EQ(cache.size(), 1u);
  // A far point changes the hull at the same address: a new entry, whose field reaches the point.
  hull.addPoint(btVector3(1.0f, 0.0f, 0.0f));
  const ConvexPolytopeField* grown = cache.field(&hull);
  ASSERT_NE(grown, nullptr);
  EXPECT_NE(grown, first);
  EXPECT_EQ(cache.size(), 2u);
  EXPECT_LT(grown->distance(Vec3(0.9, 0.0, 0.0)), 0.0);
  EXPECT_GT(first->distance(Vec3(0.9, 0.0, 0.0)), 0.0);
  // Step 5 uses the grown hull again; at step 12 the first (last used at step 0) is idle for more than 10 steps.
  cache.evictIdle(5, 10);
  EXPECT_EQ(cache.field(&hull), grown);
  cache.evictIdle(12, 10);
  EXPECT_EQ(cache.size(), 1u);
  EXPECT_EQ(cache.field(&hull), grown);
  cache.evictIdle(100, 10);
  EXPECT_EQ(cache.size(), 0u);
}

}  // namespace
}  // namespace sdfccd
