/// @file
/// @brief Contact reduction for solver mode: many point-vs-field contacts of one pair become at most 4 manifolds
/// of at most 4 points (docs/design/contact-response.md, solver mode; beyond the paper, whose penalty model uses
/// every contact).
///
/// @details Two stages, both deterministic (ties are broken by the smaller point id, never by input order):
/// 1. Greedy clustering by normal: the unassigned candidate with the smallest signed distance d seeds a
///    cluster, which takes every unassigned candidate with n . n_seed >= cos(25 deg). At most `maxClusters`
///    clusters; the candidates left over join the cluster whose mean normal is nearest (largest dot product).
/// 2. Per cluster, 4 points (Bullet's sortCachedPoints and Jolt's PruneContactPoints, deepest first so the
///    deepest point always stays), measured in the plane perpendicular to the cluster's mean normal:
///    (a) the smallest d; (b) the point farthest from (a); (c) the point that maximizes the triangle area with
///    (a, b); (d) the point that maximizes the area of the convex hull of (a, b, c, d).
///    Hysteresis: among the candidates whose criterion is within `hysteresis` (relative, 5%) of the best, a
///    point selected last step wins: first one that held the same role (a)..(d), then any. Roles matter: an
///    interior point kept for its depth would otherwise lose (a) to a corner of equal depth and drop out. So
///    the same points stay across steps and warm starting and contact callbacks stay steady.
/// A cluster of at most 4 candidates keeps them all. reduceContacts is a pure function (thread-safe).
#pragma once

#include <array>
#include <vector>

#include "sdfccd/math_types.h"

namespace sdfccd {

/// Most manifolds per pair (Bullet pairs keep a small fixed array of manifolds).
inline constexpr int kMaxContactClusters = 4;
/// Most points per manifold (btPersistentManifold's MANIFOLD_CACHE_SIZE).
inline constexpr int kMaxPointsPerCluster = 4;

/// One candidate contact of a pair (all in one frame, world in solver mode).
struct ContactCandidate {
  Vec3 position = Vec3::Zero();  ///< m, the contact point
  Vec3 normal = Vec3::UnitZ();   ///< unit normal of the contact (the field's, pushing the shell out)
  double distance = 0.0;         ///< m, signed gap along the normal (negative: penetrating)
  int point = -1;                ///< shell point id (stable across steps; ties and hysteresis use it)
};

/// Settings of reduceContacts.
struct ContactReductionSettings {
  double clusterCosine = 0.90630778703665;  ///< cos of the largest angle between a seed and a member (cos 25 deg)
  int maxClusters = kMaxContactClusters;    ///< 1..kMaxContactClusters
  double hysteresis = 0.05;                 ///< relative slack (dimensionless, [0, 1)) within which last step's wins

  /// Throws sdfccd::Error (one line naming the field) on a value out of range or NaN.
  void validate() const;
};

/// A point selected last step, and for which criterion.
struct SelectedContactPoint {
  int point = -1;  ///< shell point id
  int role = 0;    ///< 0..3: criterion (a)..(d); a cluster of <= 4 members gives its points roles in depth order

  /// Ordered by point id (the order reduceContacts expects).
  bool operator<(const SelectedContactPoint& other) const { return point < other.point; }
};

/// One manifold: a normal and up to 4 selected candidates.
struct ContactCluster {
  Vec3 normal = Vec3::UnitZ();                       ///< unit mean normal of the members
  int memberCount = 0;                               ///< candidates in the cluster (before selection)
  int selectedCount = 0;                             ///< 0..kMaxPointsPerCluster
  std::array<int, kMaxPointsPerCluster> selected{};  ///< indices into the candidates, in the order (a)..(d)
  Vec3 centroid = Vec3::Zero();                      ///< mean position of the members
  /// Mean distance of the members from their centroid in the plane normal to `normal`: the lever arm of a
  /// uniformly pressed patch's twisting friction (0.383 a for an a x a square, 2 R / 3 for a disc of radius R).
  double spread = 0.0;
};

/// The reduced contacts of one pair.
struct ReducedContacts {
  int clusterCount = 0;                                      ///< 0..maxClusters
  std::array<ContactCluster, kMaxContactClusters> clusters;  ///< in seed order (shallowest d first)

  /// Every selected candidate's point id and role, sorted by point id: pass them as `previous` next step.
  std::vector<SelectedContactPoint> selectedPoints(const std::vector<ContactCandidate>& candidates) const;
};

/// Reduces `candidates` (any order; point ids unique) to at most maxClusters clusters of at most 4 points.
/// previous: last step's ReducedContacts::selectedPoints(), sorted by point id (empty: no hysteresis). Throws
/// sdfccd::Error on bad settings, a non-finite candidate or an unsorted `previous`. Empty input gives no
/// clusters.
ReducedContacts reduceContacts(const std::vector<ContactCandidate>& candidates,
                               const ContactReductionSettings& settings = {},
                               const std::vector<SelectedContactPoint>& previous = {});

}  // namespace sdfccd
