/// @file
/// @brief What the rigid CCD tests share: bit-for-bit comparison of results, the tree-vs-linear check, the
/// bumpy random grids and the random grid cases built on them, short steps and varied settings.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/segment_reference.h"
#include "core/shell_test_util.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/mesh/procedural_meshes.h"

namespace sdfccd::test {

/// Bit-identical contacts (the tree runs the very same leaf queries as the linear traversal).
inline void expectSameContacts(const RigidCcdResult& a, const RigidCcdResult& b, const std::string& what) {
  ASSERT_EQ(a.contacts.size(), b.contacts.size()) << what;
  for (std::size_t n = 0; n < a.contacts.size(); ++n) {
    const PointContact& x = a.contacts[n];
    const PointContact& y = b.contacts[n];
    ASSERT_EQ(x.point, y.point) << what;
    EXPECT_EQ(x.state, y.state) << what;
    EXPECT_EQ(x.fraction, y.fraction) << what;
    EXPECT_EQ(x.depthAtEnd, y.depthAtEnd) << what;
    EXPECT_EQ(x.fieldNormalInSdf, y.fieldNormalInSdf) << what;
    EXPECT_EQ(x.pointNormalInShell, y.pointNormalInShell) << what;
    ASSERT_EQ(x.intervals.size(), y.intervals.size()) << what;
    for (std::size_t k = 0; k < x.intervals.size(); ++k) {
      EXPECT_EQ(x.intervals[k].begin, y.intervals[k].begin) << what;
      EXPECT_EQ(x.intervals[k].end, y.intervals[k].end) << what;
    }
  }
  EXPECT_EQ(a.firstFraction, b.firstFraction) << what;
}

template <class Field>
RigidCcdResult run(const PointTree& tree, const Field& field, const Rigid& a, const Rigid& b, RigidCcdSettings s) {
  RigidCcdResult r;
  rigidCcd(tree, field, a, b, s, r);
  return r;
}

/// Linear, tree, tree on 2 threads, linear on 2 threads: all identical. Returns the linear result.
template <class Field>
RigidCcdResult checkTreeEqualsLinear(const PointTree& tree, const Field& field, const Rigid& a, const Rigid& b,
                                     RigidCcdSettings s, const std::string& what) {
  s.useTree = false;
  s.threads = 1;
  const RigidCcdResult linear = run(tree, field, a, b, s);
  s.useTree = true;
  const RigidCcdResult treeResult = run(tree, field, a, b, s);
  expectSameContacts(linear, treeResult, what + " tree");
  s.threads = 2;
  const RigidCcdResult threaded = run(tree, field, a, b, s);
  expectSameContacts(linear, threaded, what + " tree, 2 threads");
  EXPECT_EQ(threaded.stats.nodesVisited, treeResult.stats.nodesVisited) << what;
  EXPECT_EQ(threaded.stats.segmentQueries, treeResult.stats.segmentQueries) << what;
  s.useTree = false;
  expectSameContacts(linear, run(tree, field, a, b, s), what + " linear, 2 threads");
  return linear;
}

/// A bumpy union of spheres with noise: its interpolant is steeper than 1 in places.
inline std::shared_ptr<const SdfGrid> bumpyGrid(std::uint32_t seed, double noise) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  std::vector<Vec3> centres;
  std::vector<double> radii;
  for (int k = 0; k < 4; ++k) {
    centres.emplace_back(u(rng), u(rng), u(rng));
    radii.push_back(0.3 + 0.3 * std::abs(u(rng)));
  }
  std::uniform_real_distribution<double> jitter(-noise, noise);
  return sampleGrid(Vec3i(21, 19, 23), Vec3(-1.2, -1.1, -1.3), 0.12, [&](const Vec3& p) {
    double d = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 4; ++k) d = std::min(d, (p - centres[k]).norm() - radii[k]);
    return d + jitter(rng);
  });
}

inline PointShell sampleBowl(int points, int iterations) {
  ShellSamplingSettings settings;
  settings.points = points;
  settings.iterations = iterations;
  return sampleShell(makeLathedBowl(), settings);
}

inline Box3 expanded(const Box3& box, double factor) {
  const Vec3 half = 0.5 * factor * box.sizes();
  return Box3(box.center() - half, box.center() + half);
}

/// The random grid cases of the tree-vs-linear tests, one per `field`: a bumpy grid (noisy on odd fields), a
/// random ball shell of 700 points drawn from `rng` (a sampled bowl on every third field instead), point trees of
/// branching 2, 5 and 8 in turn, and poses drawn in the grid's box expanded 3 times.
struct RandomGridCase {
  GridField grid;
  PointTree tree;
  Box3 poses;
};

inline RandomGridCase randomGridCase(std::uint32_t gridSeed, int field, std::mt19937& rng) {
  GridField grid(bumpyGrid(gridSeed, field % 2 == 0 ? 0.0 : 0.05));
  const PointShell shell = field % 3 == 2 ? sampleBowl(800, 5) : randomShell(700, 0.6, rng);
  PointTreeSettings treeSettings;
  treeSettings.branching = 2 + 3 * (field % 3);
  PointTree tree(shell, treeSettings);
  const Box3 poses = expanded(grid.grid().box(), 3.0);
  return {std::move(grid), std::move(tree), poses};
}

/// The end pose of a short step from `a` (the simulation case): a 0.2 rad turn about z, a tenth of the way to `b`.
inline Rigid shortStepFrom(const Rigid& a, const Rigid& b) {
  Rigid end = b;
  end.linear() = a.linear() * Eigen::AngleAxisd(0.2, Vec3::UnitZ()).toRotationMatrix();
  end.translation() = a.translation() + 0.1 * (b.translation() - a.translation());
  return end;
}

/// Sigma and octree mode varied with the configuration: sigma 0.05, -0.05 or 0; octree leaves, off or full.
inline RigidCcdSettings variedGridSettings(int config) {
  RigidCcdSettings s;
  s.sigma = (config % 5 == 0) ? 0.05 : (config % 5 == 1 ? -0.05 : 0.0);
  s.octree = config % 7 == 3 ? OctreeMode::Leaves : (config % 7 == 5 ? OctreeMode::Off : OctreeMode::Full);
  return s;
}

/// Sigma and mode varied with the configuration, for the sphere and the plane: sigma 0.1 on every third, all
/// intervals on even configurations and first hits on odd ones.
inline RigidCcdSettings variedSphereSettings(int config) {
  RigidCcdSettings s;
  s.sigma = config % 3 == 0 ? 0.1 : 0.0;
  s.mode = config % 2 == 0 ? CcdMode::AllIntervals : CcdMode::FirstHit;
  return s;
}

}  // namespace sdfccd::test
