/// @file
/// @brief ContactStep (see contact_step.h): a pair of ours in Bullet's narrowphase, stage by stage:
/// 1. the step's plan (the step's first pair: StepPlanner, step_planner.h);
/// 2. the mode's responder (PenaltyResponder or SolverResponder), chosen once for the pair;
/// 3. a pair the plan computed: its planned results, through the responder;
/// 4. otherwise what the shapes are (bullet_shape_fields.h), the pair's bodies (BodySteps), its roles (PairRoles),
///    each answered by the responder (its planned or its computed result), and the responder's end of the pair.
/// The response after integrateTransforms is in step_response.cpp.
#include "step/contact_step.h"

#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btEmptyCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include <iostream>
#include <optional>
#include <string>

#include "algorithm/collision_algorithm.h"
#include "parallel/narrowphase_pool.h"
#include "step/resting_pairs.h"

namespace sdfccd::bullet::detail {

ContactStep::ContactStep(const ContactSettings& settings)
    : m_log([](const std::string& line) { std::cerr << line << '\n'; }) {
  setSettings(settings);
}

ContactStep::~ContactStep() = default;

void ContactStep::setSettings(const ContactSettings& settings) {
  validateContactSettings(settings);
  // The pool starts with the first planned step that has queries: a world that never steps starts none.
  m_planner.threadsChanged(resolveThreads(settings.threads));
  m_data.settings = settings;
}

void ContactStep::registerWith(btCollisionDispatcher& dispatcher) {
  m_createFuncs.clear();
  m_createFuncs.push_back(std::make_unique<CollisionAlgorithm::CreateFunc>(this, false));
  m_createFuncs.push_back(std::make_unique<CollisionAlgorithm::CreateFunc>(this, true));
  m_createFuncs.push_back(std::make_unique<btEmptyAlgorithm::CreateFunc>());
  // Ours against every type but compounds (Bullet's compound algorithms dispatch their children back here)
  // and btEmptyShape: processPair decides, and announces what it cannot handle (bullet_shape_fields.h).
  registerOurPairs(dispatcher, CUSTOM_CONCAVE_SHAPE_TYPE, m_createFuncs[0].get(), m_createFuncs[1].get(),
                   m_createFuncs[2].get());
}

void ContactStep::processPair(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                              const btDispatcherInfo& dispatchInfo, btManifoldResult* resultOut,
                              btPersistentManifold* manifold, SolverPair* solverPair, bool closestPointsOnly) {
  // 1. The step's first pair plans the step: every pair of ours computed at once, on the pool.
  if (!closestPointsOnly && !m_planner.planned()) m_planner.plan(dispatchInfo);
  // Neither body moves (sleeping, static, kinematic at rest): no CCD, and the manifold keeps its points.
  if (!closestPointsOnly && pairAtRest(*wrap0->getCollisionObject(), *wrap1->getCollisionObject())) {
    ++m_data.stats.restingPairs;
    return;
  }
  // 2. The mode's responder. Solver mode keeps its points across steps (solver_manifolds.cpp); penalty mode, and
  // a closest-point query, report afresh each step.
  const bool solver = m_data.settings.mode == SdfccdContactMode::Solver && !closestPointsOnly && solverPair != nullptr;
  PairResponder& responder = solver ? static_cast<PairResponder&>(m_solver) : m_penalty;
  if (!solver) {
    manifold->clearManifold();
    if (!closestPointsOnly) manifold->setContactProcessingThreshold(-BT_LARGE_FLOAT);
  }
  resultOut->setPersistentManifold(manifold);
  const double timeStep = dispatchInfo.m_timeStep > 0 ? double(dispatchInfo.m_timeStep) : 1.0 / 60.0;
  const PairCall call(wrap0, wrap1, resultOut, manifold, solverPair, timeStep, closestPointsOnly);
  // 3. A pair computed in this step's parallel batch (every role of it: our shells against our fields or a plane)
  // applies its roles' results in role order, with no second setup.
  if (!closestPointsOnly && m_planner.computed(manifold)) {
    m_planner.applyPair(call, responder);
    return;
  }
  // 4. What the shapes are. Unsupported: no shape of ours (btSdfCollisionShape shares our type id), a shape we
  // cannot read, or a convex shape without volume (its shell or field would be null).
  const btCollisionShape* shape0 = wrap0->getCollisionShape();
  const btCollisionShape* shape1 = wrap1->getCollisionShape();
  RolePair pair(wrap0, wrap1, manifold, closestPointsOnly);
  const bool ours0 = pair.kind0 == ShapeKind::Ours;
  const bool ours1 = pair.kind1 == ShapeKind::Ours;
  const ShapeKind otherKind = ours0 ? pair.kind1 : pair.kind0;
  const bool convexOk = otherKind != ShapeKind::Convex ||
                        m_others.convexField(static_cast<const btConvexShape*>(ours0 ? shape1 : shape0)) != nullptr;
  if (!(ours0 || ours1) || otherKind == ShapeKind::Unsupported || !convexOk) {
    m_others.reportUnsupported(shape0, shape1, m_data.stats, m_log);
    return;
  }
  // 5. The pair's bodies: their motions over the step (a closest-point query: its own, at the poses now).
  std::optional<BodySteps::FreshScope> fresh;
  if (closestPointsOnly) fresh.emplace(m_data.bodies);
  const ContactLoads* massScaling = closestPointsOnly || solver ? nullptr : &m_data.loads;
  if (!m_data.bodies.pairOf(wrap0, wrap1, call.timeStep, massScaling, m_data.settings.penalty.caps, pair.index0,
                            pair.index1)) {
    ++m_data.stats.nonFinitePairs;
    return;
  }
  // 6. The roles, each answered by the responder; then the responder's end of the pair (solver mode: the
  // manifolds).
  responder.beginPair(call);
  m_roles.forEach(pair, responder);
  responder.endPair();
}

}  // namespace sdfccd::bullet::detail
