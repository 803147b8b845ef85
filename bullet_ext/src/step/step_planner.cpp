/// @file
/// @brief StepPlanner (see step_planner.h): the parallel narrowphase.
///
/// @details Debian's Bullet has no BT_THREADSAFE: its dispatcher, pools, manifolds and callbacks may be touched by
/// one thread only. So the parallel part is pure core CCD on copied poses and velocities, and everything that
/// touches Bullet stays on the stepping thread, in Bullet's own order.
///
/// Why algorithms that defer, not a dispatcher subclass: a ContactSystem works with any btCollisionDispatcher the
/// user built, and a subclass would have to be the one the world was constructed with. Instead the first of our
/// processCollision calls in a step plans the whole step:
/// 1. planning (serial): for every overlapping pair whose algorithm is ours and that Bullet will process
///    (needsCollision, our contacts algorithm, its solver pair made), each body's motion over the step is predicted
///    (BodySteps, from the state before any impulse of this step) and the pair's roles are enumerated (PairRoles)
///    into a queue: each role that may be deferred (our shell against our grid field or a plane) queues its query
///    with copies of what is its own and pointers to what stays put through the step (the mode's responder builds
///    the job); nothing else changes (no manifold, record, statistic or impulse);
/// 2. the queue runs on the persistent pool (narrowphase_pool.h), each query into its own result;
/// 3. Bullet goes on processing its pairs in its order; each of our roles takes its planned result instead of
///    computing it, and everything after the CCD (manifold points, records, clamps, impulses) runs as before.
/// Roles not planned (other shapes, compound children, a pair seen for the first time) compute on the spot.
///
/// Same start state for every pair: in penalty mode with ForceTiming::SameStep the impulses reach the velocities
/// in the narrowphase, so a query must not read a velocity an earlier pair changed. It never did: BodySteps caches
/// each body's predicted motion at its first pair of the step, and an impulse only reaches the bodies of the pair
/// being processed, whose motions are cached by then. Planning predicts every planned body's motion before any
/// impulse, which keeps that, so a step is bit-identical for 1, 2 or n threads and to the serial narrowphase (the
/// golden hash, tests/bullet/golden_hash_test.cpp).
///
/// What the queries touch from several threads: the tree and field of a model (read-only), the pair and role's
/// friction anchors and CCD history (one query each), the core's thread_local CCD scratch (rigid_ccd_query.h);
/// the statistics are summed when the results are taken, on the stepping thread.
#include "step/step_planner.h"

#include <BulletCollision/BroadphaseCollision/btOverlappingPairCache.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include <algorithm>
#include <chrono>

#include "algorithm/collision_algorithm.h"
#include "parallel/narrowphase_pool.h"
#include "penalty/penalty_responder.h"
#include "roles/other_shapes.h"
#include "roles/pair_roles.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "solver/solver_responder.h"
#include "step/resting_pairs.h"
#include "step/step_data.h"

namespace sdfccd::bullet::detail {
namespace {

/// Steps a convex shape's cached hull and shells outlive its last pair (ConvexShapeCache::evictIdle): a shape that
/// comes back later is rebuilt, which costs a few milliseconds once.
constexpr std::int64_t kConvexCacheIdleSteps = 1000;

/// A pair whose roles may all be planned: two of our shapes, or ours and a plane.
bool plannablePair(const btCollisionShape* a, const btCollisionShape* b) {
  const bool oursA = isSdfccdShape(a);
  const bool oursB = isSdfccdShape(b);
  if (oursA && oursB) return true;
  return (oursA && shapeKind(b) == ShapeKind::Plane) || (oursB && shapeKind(a) == ShapeKind::Plane);
}

/// The planning pass's visitor: each role that may be deferred goes to the mode's responder's queue.
template <class Responder>
class QueueRoles final : public RoleVisitorOf<QueueRoles<Responder>> {
 public:
  explicit QueueRoles(Responder& responder) : m_responder(responder) {}
  template <class Field>
  void visitField(const Role& role, const Field& field, double cellSize) {
    if constexpr (kDeferrableField<Field>) {
      if (role.deferrable) m_responder.queue(role, field, cellSize);
    }
  }

 private:
  Responder& m_responder;
};

}  // namespace

StepPlanner::StepPlanner(const ContactStep* owner, StepData& data, PairRoles& roles, OtherShapes& others,
                         PenaltyResponder& penalty, SolverResponder& solver)
    : m_owner(owner), m_data(data), m_roles(roles), m_others(others), m_penalty(penalty), m_solver(solver) {}

StepPlanner::~StepPlanner() = default;

void StepPlanner::threadsChanged(int threads) {
  if (m_pool && m_pool->threads() != threads) m_pool.reset();
}

bool StepPlanner::planned() const {
  return m_plannedStep == m_data.stepCounter;
}

void StepPlanner::plan(const btDispatcherInfo& dispatchInfo) {
  m_plannedStep = m_data.stepCounter;
  m_data.deferred.clear();
  m_data.planIncomplete.clear();
  m_others.evictIdle(m_data.stepCounter, kConvexCacheIdleSteps);  // once per step, before any pair
  if (m_world == nullptr || dispatchInfo.m_dispatchFunc != btDispatcherInfo::DISPATCH_DISCRETE) return;
  auto* dispatcher = dynamic_cast<btCollisionDispatcher*>(m_world->getDispatcher());
  // A user's near callback may process other pairs than Bullet's: then nothing is planned.
  if (dispatcher == nullptr || dispatcher->getNearCallback() != &btCollisionDispatcher::defaultNearCallback) return;
  btBroadphasePairArray& pairs = m_world->getPairCache()->getOverlappingPairArray();
  // The pairs to plan: each of our contact algorithms whose pair Bullet will process and whose roles may all be
  // planned. Collected first: the batch's buffers are sized for them (two roles each) before the workers start.
  std::vector<int>& planned = m_plannedPairs;
  planned.clear();
  for (int i = 0; i < pairs.size(); ++i) {
    auto* algorithm = dynamic_cast<CollisionAlgorithm*>(pairs[i].m_algorithm);
    if (algorithm == nullptr || !algorithm->plannable(m_owner)) continue;
    auto* object0 = static_cast<btCollisionObject*>(pairs[i].m_pProxy0->m_clientObject);
    auto* object1 = static_cast<btCollisionObject*>(pairs[i].m_pProxy1->m_clientObject);
    if (!dispatcher->needsCollision(object0, object1)) continue;
    if (!plannablePair(object0->getCollisionShape(), object1->getCollisionShape())) continue;
    planned.push_back(i);
  }
  if (planned.empty()) return;
  if (!m_pool) m_pool = std::make_unique<NarrowphasePool>(m_data.settings.threads);
  // The batch streams: the pool computes the first pairs' queries while this thread plans the next ones.
  const auto start = std::chrono::steady_clock::now();
  struct BatchScope {  // the batch is finished however the planning leaves (its workers must be done)
    explicit BatchScope(DeferredQueries& q) : queries(q) {}
    ~BatchScope() { queries.finish(); }
    DeferredQueries& queries;
  };
  // Queued roles point into the bodies' steps (penalty_role.h): planning adds at most two bodies per pair, so they
  // do not move while the workers read them.
  m_data.bodies.reserveMore(2 * planned.size());
  m_data.deferred.begin(*m_pool, 2 * planned.size());
  const BatchScope batch(m_data.deferred);
  const double timeStep = dispatchInfo.m_timeStep > 0 ? double(dispatchInfo.m_timeStep) : 1.0 / 60.0;
  for (const int i : planned) {
    auto* algorithm = static_cast<CollisionAlgorithm*>(pairs[i].m_algorithm);
    auto* object0 = static_cast<btCollisionObject*>(pairs[i].m_pProxy0->m_clientObject);
    auto* object1 = static_cast<btCollisionObject*>(pairs[i].m_pProxy1->m_clientObject);
    // The wrappers defaultNearCallback builds for the same pair.
    const btCollisionObjectWrapper wrap0(nullptr, object0->getCollisionShape(), object0, object0->getWorldTransform(),
                                         -1, -1);
    const btCollisionObjectWrapper wrap1(nullptr, object1->getCollisionShape(), object1, object1->getWorldTransform(),
                                         -1, -1);
    planPair(&wrap0, &wrap1, timeStep, algorithm->manifold(), algorithm->solverPair());
  }
  m_data.deferred.finish();
  m_data.stats.parallelWallSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void StepPlanner::planPair(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                           double timeStep, btPersistentManifold* manifold, SolverPair* solverPair) {
  // The pair's stages up to its roles, as ContactStep::processPair runs them (a planned pair is one of ours against
  // ours or a plane: always supported), with nothing reported.
  if (pairAtRest(*wrap0->getCollisionObject(), *wrap1->getCollisionObject())) return;
  const bool solver = m_data.settings.mode == SdfccdContactMode::Solver && solverPair != nullptr;
  RolePair pair(wrap0, wrap1, manifold, false);
  const ContactLoads* massScaling = solver ? nullptr : &m_data.loads;
  if (!m_data.bodies.pairOf(wrap0, wrap1, timeStep, massScaling, m_data.settings.penalty.caps, pair.index0,
                            pair.index1)) {
    return;
  }
  const PairCall call(wrap0, wrap1, nullptr, manifold, solverPair, timeStep, false);  // no result while planning
  if (solver) {
    queueRoles(m_solver, call, pair);
  } else {
    queueRoles(m_penalty, call, pair);
  }
}

template <class Responder>
void StepPlanner::queueRoles(Responder& responder, const PairCall& call, const RolePair& pair) {
  responder.beginPair(call);
  QueueRoles<Responder> queue(responder);
  m_roles.forEach(pair, queue);
}

bool StepPlanner::computed(const btPersistentManifold* manifold) {
  const std::vector<const void*>& incomplete = m_data.planIncomplete;
  return m_data.deferred.pending(manifold, 0) &&
         std::find(incomplete.begin(), incomplete.end(), manifold) == incomplete.end();
}

void StepPlanner::applyPair(const PairCall& call, PairResponder& responder) {
  responder.beginPair(call);
  // The roles in the order the enumeration runs them (their index in the pair).
  for (int role = 0;; ++role) {
    const RoleResult* result = m_data.deferred.take(call.manifold, role);
    if (result == nullptr) break;
    ++m_data.stats.deferredQueries;
    responder.applyPlanned(*result);
    if (!m_data.deferred.nextIsOf(call.manifold)) break;  // the pair's last role
  }
  responder.endPair();
}

}  // namespace sdfccd::bullet::detail
