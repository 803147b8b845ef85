/// @file
/// @brief The parallel narrowphase: SdfccdContactSystem::planStep.
///
/// @details Debian's Bullet has no BT_THREADSAFE: its dispatcher, pools, manifolds and callbacks may be touched by
/// one thread only. So the parallel part is pure core CCD on copied poses and velocities, and everything that
/// touches Bullet stays on the stepping thread, in Bullet's own order.
///
/// Why algorithms that defer, not a dispatcher subclass: registration works with any btCollisionDispatcher the
/// user built (registerSdfccdAlgorithms takes theirs), and a subclass would have to be the one the world was
/// constructed with. Instead the first of our processCollision calls in a step plans the whole step:
/// 1. planning (serial): every overlapping pair whose algorithm is ours and that Bullet will process
///    (needsCollision, our contacts algorithm, its solver pair made) runs through processPair in planning mode:
///    each body's motion over the step is predicted (bodyStep, from the state before any impulse of this step),
///    each role that may be deferred (our shell against our grid field or a plane) queues its query with copies of
///    what is its own and pointers to what stays put through the step (penalty_role.h: the job builds its input);
///    nothing else changes (no manifold, record, statistic or impulse);
/// 2. the queue runs on the persistent pool (narrowphase_pool.h), each query into its own result;
/// 3. Bullet goes on processing its pairs in its order; each of our roles takes its planned result instead of
///    computing it, and everything after the CCD (manifold points, records, clamps, impulses) runs as in the
///    serial narrowphase.
/// Roles not planned (other shapes, compound children, a pair seen for the first time) compute on the spot.
///
/// Same start state for every pair: in penalty mode with ForceTiming::SameStep the impulses reach the velocities
/// in the narrowphase, so a query must not read a velocity an earlier pair changed. The serial narrowphase never
/// does: bodyStep() caches each body's predicted motion at its first pair of the step, and an impulse only reaches
/// the bodies of the pair being processed, whose motions are cached by then. Planning predicts every planned
/// body's motion before any impulse, which keeps that, so a step is bit-identical for 1, 2 or n threads and to the
/// serial narrowphase (the golden hash, tests/bullet/golden_hash_test.cpp, pins it).
///
/// What the queries touch from several threads: the tree and field of a model (read-only), the pair and role's
/// friction anchors and CCD history (one query each), the core's thread_local CCD scratch (rigid_ccd_query.h);
/// the statistics are summed when the results are taken, on the stepping thread.
#include <BulletCollision/BroadphaseCollision/btOverlappingPairCache.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include <chrono>
#include <memory>
#include <optional>

#include "bullet_shape_fields.h"
#include "contact_step.h"
#include "deferred_queries.h"
#include "narrowphase_pool.h"
#include "sdfccd/bullet/sdfccd_collision_algorithm.h"
#include "sdfccd/bullet/sdfccd_contact_system.h"
#include "sdfccd/bullet/sdfccd_shape.h"

namespace sdfccd {
namespace {

/// Steps a convex shape's cached hull and shells outlive its last pair (ConvexShapeCache::evictIdle): a shape that
/// comes back later is rebuilt, which costs a few milliseconds once.
constexpr std::int64_t kConvexCacheIdleSteps = 1000;

/// A pair whose roles may all be planned: two of our shapes, or ours and a plane.
bool plannablePair(const btCollisionShape* a, const btCollisionShape* b) {
  using detail::ShapeKind;
  const bool oursA = isSdfccdShape(a);
  const bool oursB = isSdfccdShape(b);
  if (oursA && oursB) return true;
  return (oursA && detail::shapeKind(b) == ShapeKind::Plane) || (oursB && detail::shapeKind(a) == ShapeKind::Plane);
}

}  // namespace

void SdfccdContactSystem::planStep(const btDispatcherInfo& dispatchInfo) {
  m_plannedStep = m_stepCounter;
  m_deferred->clear();
  m_planIncomplete.clear();
  m_convexShapes->evictIdle(m_stepCounter, kConvexCacheIdleSteps);  // once per step, before any pair
  if (m_world == nullptr || dispatchInfo.m_dispatchFunc != btDispatcherInfo::DISPATCH_DISCRETE) return;
  auto* dispatcher = dynamic_cast<btCollisionDispatcher*>(m_world->getDispatcher());
  // A user's near callback may process other pairs than Bullet's: then nothing is planned.
  if (dispatcher == nullptr || dispatcher->getNearCallback() != &btCollisionDispatcher::defaultNearCallback) return;
  btBroadphasePairArray& pairs = m_world->getPairCache()->getOverlappingPairArray();
  struct PlanningScope {  // planning mode ends however processPair leaves
    explicit PlanningScope(bool& flag) : planning(flag) { planning = true; }
    ~PlanningScope() { planning = false; }
    bool& planning;
  };
  // The pairs to plan: each of our contact algorithms whose pair Bullet will process and whose roles may all be
  // planned. Collected first: the batch's buffers are sized for them (two roles each) before the workers start.
  std::vector<int>& planned = m_plannedPairs;
  planned.clear();
  for (int i = 0; i < pairs.size(); ++i) {
    auto* algorithm = dynamic_cast<SdfccdCollisionAlgorithm*>(pairs[i].m_algorithm);
    if (algorithm == nullptr || !algorithm->plannable(this)) continue;
    auto* object0 = static_cast<btCollisionObject*>(pairs[i].m_pProxy0->m_clientObject);
    auto* object1 = static_cast<btCollisionObject*>(pairs[i].m_pProxy1->m_clientObject);
    if (!dispatcher->needsCollision(object0, object1)) continue;
    if (!plannablePair(object0->getCollisionShape(), object1->getCollisionShape())) continue;
    planned.push_back(i);
  }
  if (planned.empty()) return;
  if (!m_pool) m_pool = std::make_unique<detail::NarrowphasePool>(m_settings.threads);
  // The batch streams: the pool computes the first pairs' queries while this thread plans the next ones.
  const auto start = std::chrono::steady_clock::now();
  struct BatchScope {  // the batch is finished however the planning leaves (its workers must be done)
    explicit BatchScope(detail::DeferredQueries& q) : queries(q) {}
    ~BatchScope() { queries.finish(); }
    detail::DeferredQueries& queries;
  };
  // Queued roles point into m_bodies (penalty_role.h): planning adds at most two bodies per pair, so it does not
  // move while the workers read it.
  m_bodies.reserve(m_bodies.size() + 2 * planned.size());
  m_deferred->begin(*m_pool, 2 * planned.size());
  const BatchScope batch(*m_deferred);
  std::optional<PlanningScope> scope(std::in_place, m_planning);
  for (const int i : planned) {
    auto* algorithm = static_cast<SdfccdCollisionAlgorithm*>(pairs[i].m_algorithm);
    auto* object0 = static_cast<btCollisionObject*>(pairs[i].m_pProxy0->m_clientObject);
    auto* object1 = static_cast<btCollisionObject*>(pairs[i].m_pProxy1->m_clientObject);
    // The wrappers defaultNearCallback builds for the same pair.
    const btCollisionObjectWrapper wrap0(nullptr, object0->getCollisionShape(), object0, object0->getWorldTransform(),
                                         -1, -1);
    const btCollisionObjectWrapper wrap1(nullptr, object1->getCollisionShape(), object1, object1->getWorldTransform(),
                                         -1, -1);
    // No result object: planning only queues (processPair touches resultOut when it applies, never while planning).
    processPair(&wrap0, &wrap1, dispatchInfo, nullptr, algorithm->manifold(), algorithm->solverPair(), false);
  }
  scope.reset();
  m_deferred->finish();
  m_stats.parallelWallSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void SdfccdContactSystem::applyPlannedPair(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                                           const btDispatcherInfo& dispatchInfo, btManifoldResult* resultOut,
                                           btPersistentManifold* manifold, SdfccdSolverPair* solverPair) {
  if (solverPair != nullptr) {
    m_candidates.clear();
    m_candidateBounce.clear();
    m_candidateDistance.clear();
    m_candidateMargin = 0.0;
    m_solverTimeStep = dispatchInfo.m_timeStep > 0 ? double(dispatchInfo.m_timeStep) : 1.0 / 60.0;
  }
  // The roles in the order processPair runs them (their index in the pair).
  for (int role = 0;; ++role) {
    const detail::RoleResult* result = m_deferred->take(manifold, role);
    if (result == nullptr) break;
    ++m_stats.deferredQueries;
    if (solverPair != nullptr) {
      applySolverRole(*result);
    } else {
      applyPenaltyRole(*result, resultOut, false);
    }
    if (!m_deferred->nextIsOf(manifold)) break;  // the pair's last role
  }
  if (solverPair == nullptr) return;
  const bool swapped = manifold->getBody0() != wrap0->getCollisionObject();
  writeSolverManifolds(swapped ? wrap1 : wrap0, swapped ? wrap0 : wrap1, manifold, *solverPair);
}

}  // namespace sdfccd
