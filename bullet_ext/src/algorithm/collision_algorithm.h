/// @file
/// @brief CollisionAlgorithm: Bullet's per-pair entry point for SdfccdShape pairs (paper Section 5); the work is
/// done by ContactStep::processPair.
///
/// @details One instance per overlapping pair, pool-allocated by the dispatcher. It holds only two pointers
/// and two flags (its size is checked at compile time against btConvexConvexAlgorithm, one of the built-in
/// algorithms whose largest size sets the pool's element size), so it always fits the collision algorithm
/// pool; scratch memory lives in the contact system. It owns one persistent manifold through which contacts are
/// reported and, in solver mode, up to three more (one per contact cluster) behind one pointer, released when unused
/// and in the destructor.
///
/// Ownership: users never create one; the dispatcher does, through the create functions the contact step owns
/// (ContactSystem registers them), and frees it with the pair. It points at the contact step without owning it.
#pragma once

#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionCreateFunc.h>

namespace sdfccd::bullet::detail {

class ContactStep;
struct SolverPair;

class CollisionAlgorithm : public btCollisionAlgorithm {
 public:
  CollisionAlgorithm(const btCollisionAlgorithmConstructionInfo& info, const btCollisionObjectWrapper* wrap0,
                     const btCollisionObjectWrapper* wrap1, ContactStep* step, bool closestPointsOnly);
  ~CollisionAlgorithm() override;

  void processCollision(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                        const btDispatcherInfo& dispatchInfo, btManifoldResult* resultOut) override;
  /// Our CCD runs in processCollision; Bullet's TOI interface is not used (returns 1).
  btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                 btManifoldResult*) override {
    return btScalar(1);
  }
  void getAllContactManifolds(btManifoldArray& manifoldArray) override;

  /// The step planner's question (step_planner.cpp): a contacts algorithm of `step` whose pair state exists
  /// (solver mode: made at its first processCollision), so that planning its pair changes nothing.
  bool plannable(const ContactStep* step) const;
  btPersistentManifold* manifold() const { return m_manifold; }
  SolverPair* solverPair() const { return m_solverPair; }

  /// Creates CollisionAlgorithm for one dispatcher entry.
  struct CreateFunc : public btCollisionAlgorithmCreateFunc {
    CreateFunc(ContactStep* step, bool closestPointsOnly) : m_step(step), m_closestPointsOnly(closestPointsOnly) {}
    btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& info,
                                                   const btCollisionObjectWrapper* wrap0,
                                                   const btCollisionObjectWrapper* wrap1) override;
    ContactStep* m_step;
    bool m_closestPointsOnly;
  };

 private:
  ContactStep* m_step;
  btPersistentManifold* m_manifold = nullptr;
  SolverPair* m_solverPair = nullptr;  // solver mode: extra manifolds and last step's selection (owned)
  bool m_closestPointsOnly;
};

}  // namespace sdfccd::bullet::detail
