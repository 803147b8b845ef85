/// @file
/// @brief CollisionAlgorithm (see collision_algorithm.h).
#include "algorithm/collision_algorithm.h"

#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btConvexConvexAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include "solver/solver_manifolds.h"
#include "step/contact_step.h"

namespace sdfccd::bullet::detail {

// The dispatcher's pool element size is the largest built-in algorithm; btConvexConvexAlgorithm is among
// them, so anything no larger always fits (Bullet checks this only with a debug assert).
static_assert(sizeof(CollisionAlgorithm) <= sizeof(btConvexConvexAlgorithm),
              "CollisionAlgorithm must fit Bullet's collision algorithm pool");

CollisionAlgorithm::CollisionAlgorithm(const btCollisionAlgorithmConstructionInfo& info,
                                       const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                                       ContactStep* step, bool closestPointsOnly)
    : btCollisionAlgorithm(info), m_step(step), m_closestPointsOnly(closestPointsOnly) {
  m_manifold = m_dispatcher->getNewManifold(wrap0->getCollisionObject(), wrap1->getCollisionObject());
  // Penalty mode: the solver turns only points with distance <= this threshold into constraints, so ours stay
  // reports. Solver mode sets Bullet's own value back when it writes the manifold (solver_manifolds.cpp).
  m_manifold->setContactProcessingThreshold(-BT_LARGE_FLOAT);
}

CollisionAlgorithm::~CollisionAlgorithm() {
  destroySolverPair(m_solverPair, m_dispatcher);
  if (m_manifold != nullptr) m_dispatcher->releaseManifold(m_manifold);
}

void CollisionAlgorithm::processCollision(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                                          const btDispatcherInfo& dispatchInfo, btManifoldResult* resultOut) {
  if (m_solverPair == nullptr && !m_closestPointsOnly && m_step->settings().mode == SdfccdContactMode::Solver) {
    m_solverPair = createSolverPair(m_dispatcher, m_manifold);
  }
  m_step->processPair(wrap0, wrap1, dispatchInfo, resultOut, m_manifold, m_solverPair, m_closestPointsOnly);
}

bool CollisionAlgorithm::plannable(const ContactStep* step) const {
  if (step != m_step || m_closestPointsOnly || m_manifold == nullptr) return false;
  return m_solverPair != nullptr || m_step->settings().mode != SdfccdContactMode::Solver;
}

void CollisionAlgorithm::getAllContactManifolds(btManifoldArray& manifoldArray) {
  if (m_manifold != nullptr) manifoldArray.push_back(m_manifold);
  solverPairManifolds(m_solverPair, manifoldArray);
}

btCollisionAlgorithm* CollisionAlgorithm::CreateFunc::CreateCollisionAlgorithm(
    btCollisionAlgorithmConstructionInfo& info, const btCollisionObjectWrapper* wrap0,
    const btCollisionObjectWrapper* wrap1) {
  void* memory = info.m_dispatcher1->allocateCollisionAlgorithm(sizeof(CollisionAlgorithm));
  return new (memory) CollisionAlgorithm(info, wrap0, wrap1, m_step, m_closestPointsOnly);
}

}  // namespace sdfccd::bullet::detail
