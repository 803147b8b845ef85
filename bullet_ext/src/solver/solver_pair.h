/// @file
/// @brief SolverPair: what one pair keeps between steps in solver mode (design note Sections 3.1 and 3.2). Owned by
/// the pair's CollisionAlgorithm (one pointer, so the algorithm still fits Bullet's pool), written by
/// solver_manifolds.cpp.
#pragma once

#include <array>
#include <vector>

#include "sdfccd/response/contact_reduction.h"

class btDispatcher;
class btPersistentManifold;

namespace sdfccd::bullet::detail {

struct SolverPair {
  btDispatcher* dispatcher = nullptr;  ///< hands out and takes back the extra manifolds
  /// Manifolds of clusters 2..4 (the algorithm's own manifold carries one cluster); null when unused.
  std::array<btPersistentManifold*, kMaxContactClusters - 1> extra{};
  std::vector<SelectedContactPoint> previous;  ///< last step's selection (reduceContacts' hysteresis)
  double bulletBreakingThreshold = 0.0;        ///< m: Bullet's own value for the pair (the floor of ours)
};

}  // namespace sdfccd::bullet::detail
