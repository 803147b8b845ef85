/// @file
/// @brief PairResponder: what answers a pair's roles in one contact mode (PenaltyResponder, SolverResponder), chosen
/// once per pair from the mode. It receives the pair's call, then each role with its field (computing its result,
/// or applying the one the step's plan computed), then the end of the pair.
#pragma once

#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include "roles/role.h"

class btManifoldResult;

namespace sdfccd::bullet::detail {

struct RoleResult;
struct SolverPair;

/// One call of a pair, as the responders see it.
struct PairCall {
  const btCollisionObjectWrapper* wrap0 = nullptr;
  const btCollisionObjectWrapper* wrap1 = nullptr;
  btManifoldResult* resultOut = nullptr;  // null while the step is planned
  btPersistentManifold* manifold = nullptr;
  SolverPair* solverPair = nullptr;  // solver mode: the pair's extra manifolds and last selection
  double timeStep = 0.0;             // s
  bool swapped = false;              // the manifold's body 0 is wrap1's object (Bullet hands pairs in either order)
  bool closestPointsOnly = false;    // a contactTest query: the points inside at the current poses, nothing changes

  PairCall(const btCollisionObjectWrapper* first, const btCollisionObjectWrapper* second, btManifoldResult* result,
           btPersistentManifold* pairManifold, SolverPair* pairSolver, double step, bool closestPoints)
      : wrap0(first),
        wrap1(second),
        resultOut(result),
        manifold(pairManifold),
        solverPair(pairSolver),
        timeStep(step),
        swapped(pairManifold->getBody0() != first->getCollisionObject()),
        closestPointsOnly(closestPoints) {}
};

class PairResponder : public RoleVisitor {
 public:
  /// Before the pair's roles.
  virtual void beginPair(const PairCall& call) = 0;
  /// A role's result the step's plan computed (pairs whose roles were all planned).
  virtual void applyPlanned(const RoleResult& result) = 0;
  /// After the pair's roles.
  virtual void endPair() = 0;

 protected:
  ~PairResponder() = default;
};

}  // namespace sdfccd::bullet::detail
