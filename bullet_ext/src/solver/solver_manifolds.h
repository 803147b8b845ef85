/// @file
/// @brief Solver mode, the whole pair (see solver_manifolds.cpp): a pair's candidates reduced and written into its
/// manifolds, and the pair state (SolverPair) the collision algorithm owns.
#pragma once

#include <vector>

#include "sdfccd/response/contact_reduction.h"
#include "solver/solver_pair.h"

class btCollisionObjectWrapper;
class btDispatcher;
class btPersistentManifold;
template <typename T>
class btAlignedObjectArray;
typedef btAlignedObjectArray<btPersistentManifold*> btManifoldArray;

namespace sdfccd::bullet::detail {

/// The candidates of a pair's roles (solver_role.h), at the step's start, with their rebound and solver distance.
struct SolverCandidates {
  std::vector<ContactCandidate> points;
  std::vector<double> bounce;    // per candidate, added to its restitution (solver_role.cpp)
  std::vector<double> distance;  // per candidate, the distance Bullet's solver gets (m)
  double margin = 0.0;           // the pair's largest speculative margin (m)
};

/// The world's friction as the solver's rows get it: off (no friction, rolling or spinning rows), the bodies'
/// combined coefficient, or one coefficient for every pair.
struct SolverFriction {
  bool enabled = true;
  bool fromBodies = true;
  double coefficient = 0.5;  // when not from the bodies
};

/// Reduces the candidates and writes each cluster into one of the pair's manifolds (`primary`, the algorithm's own,
/// or the pair's extra ones). `wrapA` holds the manifold's body 0.
void writeSolverManifolds(const btCollisionObjectWrapper* wrapA, const btCollisionObjectWrapper* wrapB,
                          btPersistentManifold* primary, SolverPair& pair, const SolverCandidates& candidates,
                          const SolverFriction& friction);

/// A new solver pair for an algorithm whose own manifold is `primary`.
SolverPair* createSolverPair(btDispatcher* dispatcher, const btPersistentManifold* primary);
/// Releases a solver pair's extra manifolds (through `dispatcher`) and deletes it. Null is allowed.
void destroySolverPair(SolverPair* pair, btDispatcher* dispatcher);
/// Appends the solver pair's manifolds (the extra ones; the algorithm adds its own).
void solverPairManifolds(const SolverPair* pair, btManifoldArray& manifoldArray);

}  // namespace sdfccd::bullet::detail
