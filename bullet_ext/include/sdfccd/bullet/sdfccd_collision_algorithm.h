/// @file
/// @brief SdfccdCollisionAlgorithm: Bullet's per-pair entry point for SdfccdShape pairs (paper Section 5);
/// the work is done by SdfccdContactSystem::processPair.
///
/// @details One instance per overlapping pair, pool-allocated by the dispatcher. It holds only two pointers
/// and two flags (its size is checked at compile time against btConvexConvexAlgorithm, one of the built-in
/// algorithms whose largest size sets the pool's element size), so it always fits the collision algorithm
/// pool; scratch memory lives in the contact system. It owns one persistent manifold through which contacts are
/// reported and, in solver mode, up to three more (one per contact cluster) behind one pointer, released when unused
/// and in the destructor.
///
/// Ownership: users never create one; the dispatcher does, through the create functions the contact system owns
/// (registerSdfccdAlgorithms), and frees it with the pair. It points at the contact system without owning it.
#pragma once

#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionCreateFunc.h>

namespace sdfccd {

class SdfccdContactSystem;
struct SdfccdSolverPair;

class SdfccdCollisionAlgorithm : public btCollisionAlgorithm {
 public:
  SdfccdCollisionAlgorithm(const btCollisionAlgorithmConstructionInfo& info, const btCollisionObjectWrapper* wrap0,
                           const btCollisionObjectWrapper* wrap1, SdfccdContactSystem* system, bool closestPointsOnly);
  ~SdfccdCollisionAlgorithm() override;

  void processCollision(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                        const btDispatcherInfo& dispatchInfo, btManifoldResult* resultOut) override;
  /// Our CCD runs in processCollision; Bullet's TOI interface is not used (returns 1).
  btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                 btManifoldResult*) override {
    return btScalar(1);
  }
  void getAllContactManifolds(btManifoldArray& manifoldArray) override;

  /// The parallel step's planning (sdfccd_parallel_step.cpp): a contacts algorithm of `system` whose pair state
  /// exists (solver mode: made at its first processCollision), so that planning its pair changes nothing.
  bool plannable(const SdfccdContactSystem* system) const;
  btPersistentManifold* manifold() const { return m_manifold; }
  SdfccdSolverPair* solverPair() const { return m_solverPair; }

  /// Creates SdfccdCollisionAlgorithm for one dispatcher entry.
  struct CreateFunc : public btCollisionAlgorithmCreateFunc {
    CreateFunc(SdfccdContactSystem* system, bool closestPointsOnly)
        : m_system(system), m_closestPointsOnly(closestPointsOnly) {}
    btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& info,
                                                   const btCollisionObjectWrapper* wrap0,
                                                   const btCollisionObjectWrapper* wrap1) override;
    SdfccdContactSystem* m_system;
    bool m_closestPointsOnly;
  };

 private:
  SdfccdContactSystem* m_system;
  btPersistentManifold* m_manifold = nullptr;
  SdfccdSolverPair* m_solverPair = nullptr;  // solver mode: extra manifolds and last step's selection (owned)
  bool m_closestPointsOnly;
};

}  // namespace sdfccd
