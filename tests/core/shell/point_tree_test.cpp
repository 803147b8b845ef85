/// @file
/// @brief The nested point tree: nesting, bounding, one leaf per point, breadth-first layout; degenerate
/// shells (one point, coincident points); a 10^5-point build.
#include "sdfccd/shell/point_tree.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "core/shell_test_util.h"
#include "sdfccd/error.h"
#include "sdfccd/mesh/procedural_meshes.h"

namespace sdfccd {
namespace {

// Every invariant the traversal relies on, checked by brute force.
void checkInvariants(const PointTree& tree) {
  const int nodes = tree.nodeCount();
  const int points = tree.pointCount();
  ASSERT_GE(nodes, points);
  // One leaf per point; leaves have radius 0.
  std::vector<int> leafCount(points, 0);
  for (int n = 0; n < nodes; ++n) {
    if (!tree.isLeaf(n)) continue;
    ++leafCount[tree.point(n)];
    EXPECT_EQ(tree.radius(n), 0.0);
    EXPECT_EQ(tree.leafOf(tree.point(n)), n);
  }
  for (int p = 0; p < points; ++p) EXPECT_EQ(leafCount[p], 1) << "point " << p;
  // Breadth-first layout: children contiguous, after their parent, one level down; levels contiguous.
  std::vector<int> level(nodes, -1);
  level[0] = 0;
  std::vector<int> parents(nodes, 0);
  for (int n = 0; n < nodes; ++n) {
    ASSERT_GE(level[n], 0) << "node " << n << " has no parent";
    EXPECT_GE(n, tree.levelBegin(level[n]));
    EXPECT_LT(n, tree.levelBegin(level[n] + 1));
    if (tree.isLeaf(n)) {
      EXPECT_EQ(tree.firstChild(n), -1);
      continue;
    }
    EXPECT_GE(tree.childCount(n), 2);
    EXPECT_GT(tree.firstChild(n), n);
    for (int c = tree.firstChild(n); c < tree.firstChild(n) + tree.childCount(n); ++c) {
      ASSERT_LT(c, nodes);
      ++parents[c];
      level[c] = level[n] + 1;
    }
    // Nesting: the node's point is its first child's point.
    EXPECT_EQ(tree.point(tree.firstChild(n)), tree.point(n));
  }
  for (int n = 1; n < nodes; ++n) EXPECT_EQ(parents[n], 1);
  // Nesting as sets: the points of level l (leaves above carried down) are a subset of those of level l + 1.
  std::set<int> carried;
  std::set<int> previous;
  for (int l = 0; l < tree.levelCount(); ++l) {
    std::set<int> current = carried;
    for (int n = tree.levelBegin(l); n < tree.levelBegin(l + 1); ++n) {
      current.insert(tree.point(n));
      if (tree.isLeaf(n)) carried.insert(tree.point(n));
    }
    for (int p : previous) EXPECT_TRUE(current.count(p)) << "level " << l << " lost point " << p;
    previous = current;
  }
  EXPECT_EQ(static_cast<int>(previous.size()), points);
  // Bounding: every node's sphere holds every point of its subtree; the centre is the node's point.
  for (int n = 0; n < nodes; ++n) {
    EXPECT_EQ(tree.center(n), tree.shell().positions[tree.point(n)]);
    std::vector<int> under;
    tree.pointsUnder(n, under);
    double farthest = 0.0;
    for (int p : under) farthest = std::max(farthest, (tree.shell().positions[p] - tree.center(n)).norm());
    EXPECT_LE(farthest, tree.radius(n)) << "node " << n;
    if (n == 0) {
      EXPECT_EQ(static_cast<int>(under.size()), points);
    }
  }
}

TEST(PointTree, RandomShellsSatisfyNestingAndBounding) {
  std::mt19937 rng(3);
  for (int count : {1, 2, 3, 7, 8, 9, 64, 65, 500, 2000}) {
    for (int branching : {2, 4, 8}) {
      PointTreeSettings settings;
      settings.branching = branching;
      const PointTree tree(test::randomShell(count, 1.0 + count * 0.01, rng), settings);
      SCOPED_TRACE("count " + std::to_string(count) + ", branching " + std::to_string(branching));
      checkInvariants(tree);
      for (int n = 0; n < tree.nodeCount(); ++n) EXPECT_LE(tree.childCount(n), branching);
    }
  }
}

TEST(PointTree, CoincidentAndClusteredPointsStillSplit) {
  PointShell shell;
  for (int n = 0; n < 50; ++n) {
    shell.positions.push_back(n < 40 ? Vec3(1.0, 2.0, 3.0) : Vec3(n, 0.0, 0.0));
    shell.normals.push_back(Vec3::UnitZ());
  }
  const PointTree tree(shell);
  checkInvariants(tree);
}

TEST(PointTree, ShellOfAMeshAndATenToTheFiveBuild) {
  const PointTree bowl(shellFromVertices(makeLathedBowl()));
  checkInvariants(bowl);
  std::mt19937 rng(5);
  const PointTree big(test::randomShell(100000, 1.0, rng));
  EXPECT_EQ(big.pointCount(), 100000);
  EXPECT_LE(big.levelCount(), 12);
  // Bounding on a sample of nodes (the full brute force is quadratic).
  for (int n = 0; n < big.nodeCount(); n += 997) {
    std::vector<int> under;
    big.pointsUnder(n, under);
    for (int p : under) EXPECT_LE((big.shell().positions[p] - big.center(n)).norm(), big.radius(n));
  }
}

TEST(PointTree, RejectsBadInput) {
  EXPECT_THROW(PointTree(PointShell{}), Error);
  PointShell mismatched;
  mismatched.positions = {Vec3::Zero()};
  EXPECT_THROW(PointTree{mismatched}, Error);
  PointShell nonUnit;
  nonUnit.positions = {Vec3::Zero()};
  nonUnit.normals = {Vec3(0, 0, 2)};
  EXPECT_THROW(PointTree{nonUnit}, Error);
  PointShell fine;
  fine.positions = {Vec3::Zero()};
  fine.normals = {Vec3::UnitX()};
  PointTreeSettings settings;
  settings.branching = 1;
  EXPECT_THROW(PointTree(fine, settings), Error);
}

}  // namespace
}  // namespace sdfccd
