/// @file
/// @brief SdfccdCollisionAlgorithm (see sdfccd_collision_algorithm.h).
#include "sdfccd/bullet/sdfccd_collision_algorithm.h"

#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btConvexConvexAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include "sdfccd/bullet/sdfccd_contact_system.h"

namespace sdfccd {

// The dispatcher's pool element size is the largest built-in algorithm; btConvexConvexAlgorithm is among
// them, so anything no larger always fits (Bullet checks this only with a debug assert).
static_assert(sizeof(SdfccdCollisionAlgorithm) <= sizeof(btConvexConvexAlgorithm),
              "SdfccdCollisionAlgorithm must fit Bullet's collision algorithm pool");

SdfccdCollisionAlgorithm::SdfccdCollisionAlgorithm(const btCollisionAlgorithmConstructionInfo& info,
                                                   const btCollisionObjectWrapper* wrap0,
                                                   const btCollisionObjectWrapper* wrap1, SdfccdContactSystem* system,
                                                   bool closestPointsOnly)
    : btCollisionAlgorithm(info), m_system(system), m_closestPointsOnly(closestPointsOnly) {
  m_manifold = m_dispatcher->getNewManifold(wrap0->getCollisionObject(), wrap1->getCollisionObject());
  // Penalty mode: the solver turns only points with distance <= this threshold into constraints, so ours stay
  // reports. Solver mode sets Bullet's own value back in processPair.
  m_manifold->setContactProcessingThreshold(-BT_LARGE_FLOAT);
}

SdfccdCollisionAlgorithm::~SdfccdCollisionAlgorithm() {
  SdfccdContactSystem::destroySolverPair(m_solverPair, m_dispatcher);
  if (m_manifold != nullptr) m_dispatcher->releaseManifold(m_manifold);
}

void SdfccdCollisionAlgorithm::processCollision(const btCollisionObjectWrapper* wrap0,
                                                const btCollisionObjectWrapper* wrap1,
                                                const btDispatcherInfo& dispatchInfo, btManifoldResult* resultOut) {
  if (m_solverPair == nullptr && !m_closestPointsOnly && m_system->settings().mode == SdfccdContactMode::Solver) {
    m_solverPair = SdfccdContactSystem::createSolverPair(m_dispatcher, m_manifold);
  }
  m_system->processPair(wrap0, wrap1, dispatchInfo, resultOut, m_manifold, m_solverPair, m_closestPointsOnly);
}

bool SdfccdCollisionAlgorithm::plannable(const SdfccdContactSystem* system) const {
  if (system != m_system || m_closestPointsOnly || m_manifold == nullptr) return false;
  return m_solverPair != nullptr || m_system->settings().mode != SdfccdContactMode::Solver;
}

void SdfccdCollisionAlgorithm::getAllContactManifolds(btManifoldArray& manifoldArray) {
  if (m_manifold != nullptr) manifoldArray.push_back(m_manifold);
  SdfccdContactSystem::solverPairManifolds(m_solverPair, manifoldArray);
}

btCollisionAlgorithm* SdfccdCollisionAlgorithm::CreateFunc::CreateCollisionAlgorithm(
    btCollisionAlgorithmConstructionInfo& info, const btCollisionObjectWrapper* wrap0,
    const btCollisionObjectWrapper* wrap1) {
  void* memory = info.m_dispatcher1->allocateCollisionAlgorithm(sizeof(SdfccdCollisionAlgorithm));
  return new (memory) SdfccdCollisionAlgorithm(info, wrap0, wrap1, m_system, m_closestPointsOnly);
}

}  // namespace sdfccd
