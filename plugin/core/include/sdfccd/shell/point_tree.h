/// @file
/// @brief PointTree: the nested point tree of Barbic and James over a point shell (paper Section 3.3, ref. [4]).
///
/// @details Every node is one shell point (its centre) with a sphere that bounds every point of its subtree.
/// Nesting: an inner node's point is the point of its first child, so the points of level l are a subset of
/// those of level l + 1 (a leaf stands for its point at every deeper level). Leaves are single points
/// (radius 0), one per shell point.
///
/// Built top down: a node's points are split into up to `branching` clusters seeded by farthest-point
/// sampling from the node's own point (which seeds the first cluster), each point joining its nearest seed,
/// with a few medoid refinements; the radius is the largest distance from the node's point to a point below.
/// Nodes are stored breadth first in parallel arrays (root = 0; the children of a node are contiguous and
/// levels are contiguous), so a traversal streams through memory. O(N log N); well under a second for
/// 10^5 points.
///
/// Immutable after construction; any number of threads may read it.
#pragma once

#include <cstdint>
#include <vector>

#include "sdfccd/instance_id.h"
#include "sdfccd/math_types.h"
#include "sdfccd/shell/point_shell.h"

namespace sdfccd {

/// Settings of the tree build.
struct PointTreeSettings {
  int branching = 8;    ///< children per inner node (>= 2)
  int refinements = 2;  ///< medoid refinements of each split (0: farthest-point seeds only)
};

class PointTree {
 public:
  PointTree() = default;
  /// Builds the tree over `shell` (which it keeps). Throws sdfccd::Error on an empty or invalid shell or
  /// absurd settings.
  explicit PointTree(PointShell shell, const PointTreeSettings& settings = {});

  const PointShell& shell() const { return m_shell; }
  int pointCount() const { return static_cast<int>(m_shell.size()); }
  int nodeCount() const { return static_cast<int>(m_nodePoint.size()); }
  /// Number of levels (depth of the deepest leaf + 1).
  int levelCount() const { return static_cast<int>(m_levelBegin.size()) - 1; }
  /// Nodes of level l are [levelBegin(l), levelBegin(l + 1)).
  int levelBegin(int level) const { return m_levelBegin[level]; }

  // Per node, breadth-first order (root = 0):
  const Vec3& center(int node) const { return m_center[node]; }  ///< the node's point, shell frame
  double radius(int node) const { return m_radius[node]; }       ///< bounds the subtree (model units)
  int point(int node) const { return m_nodePoint[node]; }        ///< shell index of the node's point
  int firstChild(int node) const { return m_firstChild[node]; }  ///< -1 for leaves
  int childCount(int node) const { return m_childCount[node]; }  ///< 0 for leaves
  bool isLeaf(int node) const { return m_childCount[node] == 0; }
  /// The leaf of shell point p.
  int leafOf(int point) const { return m_leafOfPoint[point]; }
  /// The shell's curvature at point p (rad per model unit; shellCurvatures, point_shell.h): which
  /// surface of a pair gives a contact's normal.
  double curvature(int point) const { return m_curvature[static_cast<std::size_t>(point)]; }
  const std::vector<double>& curvatures() const { return m_curvature; }

  // The arrays, for traversals that stream through them.
  const std::vector<Vec3>& centers() const { return m_center; }
  const std::vector<double>& radii() const { return m_radius; }
  const std::vector<int>& nodePoints() const { return m_nodePoint; }
  const std::vector<int>& firstChildren() const { return m_firstChild; }
  const std::vector<int>& childCounts() const { return m_childCount; }

  /// Appends the shell indices of every point below `node` (itself included) to `out`.
  void pointsUnder(int node, std::vector<int>& out) const;

  /// Names this tree's contents (never reused, unlike its address): keys caches such as RigidCcdCoherence.
  std::uint64_t instanceId() const { return m_id.value(); }

 private:
  InstanceId m_id;
  PointShell m_shell;
  std::vector<double> m_curvature;
  std::vector<Vec3> m_center;
  std::vector<double> m_radius;
  std::vector<int> m_nodePoint;
  std::vector<int> m_firstChild;
  std::vector<int> m_childCount;
  std::vector<int> m_levelBegin;
  std::vector<int> m_leafOfPoint;
};

}  // namespace sdfccd
