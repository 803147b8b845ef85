/// @file
/// @brief Contact reduction (contact_reduction.h): a flat patch reduces to its corners (and its deepest point), two
/// faces of a box give two clusters, hysteresis keeps the same points under jitter, leftovers join the nearest cluster,
/// at most 4 candidates are all kept, and the input order does not matter.
#include "sdfccd/response/contact_reduction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

// A 10 x 10 patch of points 1 cm apart on the plane z = z0 with normal +z; id = 10 i + j (+ idOffset).
std::vector<ContactCandidate> flatPatch(double depth, int idOffset = 0) {
  std::vector<ContactCandidate> out;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j)
      out.push_back({Vec3(0.01 * i, 0.01 * j, 0.0), Vec3::UnitZ(), -depth, 10 * i + j + idOffset});
  }
  return out;
}

// The point ids of a reduction, sorted.
std::vector<int> ids(const std::vector<SelectedContactPoint>& points) {
  std::vector<int> out;
  for (const SelectedContactPoint& p : points) out.push_back(p.point);
  return out;
}

std::vector<int> selectedIds(const ReducedContacts& reduced, const std::vector<ContactCandidate>& candidates,
                             int cluster) {
  std::vector<int> ids;
  for (int i = 0; i < reduced.clusters[cluster].selectedCount; ++i) {
    ids.push_back(candidates[reduced.clusters[cluster].selected[i]].point);
  }
  return ids;
}

TEST(ContactReduction, FlatPatchKeepsItsCorners) {
  const std::vector<ContactCandidate> patch = flatPatch(0.001);
  const ReducedContacts reduced = reduceContacts(patch);
  ASSERT_EQ(reduced.clusterCount, 1);
  EXPECT_EQ(reduced.clusters[0].memberCount, 100);
  EXPECT_NEAR((reduced.clusters[0].normal - Vec3::UnitZ()).norm(), 0.0, 1e-15);
  // Equal depths: (a) is the smallest id, corner 0; (b) the opposite corner; (c), (d) the others (by id on ties).
  EXPECT_EQ(selectedIds(reduced, patch, 0), (std::vector<int>{0, 99, 9, 90}));
  EXPECT_EQ(ids(reduced.selectedPoints(patch)), (std::vector<int>{0, 9, 90, 99}));
}

TEST(ContactReduction, TheDeepestPointAlwaysStays) {
  std::vector<ContactCandidate> patch = flatPatch(0.001);
  patch[44].distance = -0.002;  // an interior point, deeper
  const ReducedContacts reduced = reduceContacts(patch);
  ASSERT_EQ(reduced.clusterCount, 1);
  // (a) the deepest, (b) the corner farthest from it, (c) the largest triangle, (d) the largest hull.
  EXPECT_EQ(selectedIds(reduced, patch, 0), (std::vector<int>{44, 99, 9, 90}));
}

TEST(ContactReduction, TwoFacesOfABoxGiveTwoClusters) {
  std::vector<ContactCandidate> candidates;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      candidates.push_back({Vec3(0.02 * i, 0.02 * j, 0.1), Vec3::UnitZ(), -0.001, 100 + 6 * i + j});   // top
      candidates.push_back({Vec3(0.1, 0.02 * j, 0.02 * i), Vec3::UnitX(), -0.0005, 200 + 6 * i + j});  // side
    }
  }
  const ReducedContacts reduced = reduceContacts(candidates);
  ASSERT_EQ(reduced.clusterCount, 2);
  // Seeds shallowest first: the top (d = -1 mm) before the side (-0.5 mm).
  EXPECT_NEAR((reduced.clusters[0].normal - Vec3::UnitZ()).norm(), 0.0, 1e-15);
  EXPECT_NEAR((reduced.clusters[1].normal - Vec3::UnitX()).norm(), 0.0, 1e-15);
  EXPECT_EQ(reduced.clusters[0].memberCount, 36);
  EXPECT_EQ(reduced.clusters[1].memberCount, 36);
  EXPECT_EQ(selectedIds(reduced, candidates, 0), (std::vector<int>{100, 135, 105, 130}));
  EXPECT_EQ(selectedIds(reduced, candidates, 1), (std::vector<int>{200, 235, 205, 230}));
}

TEST(ContactReduction, NormalsWithin25DegreesShareACluster) {
  auto tilted = [](double degrees) {
    const double r = degrees * 3.14159265358979323846 / 180.0;
    return Vec3(std::sin(r), 0.0, std::cos(r));
  };
  const std::vector<ContactCandidate> candidates = {{Vec3(0, 0, 0), tilted(0), -0.002, 1},
                                                    {Vec3(1, 0, 0), tilted(24), -0.001, 2},
                                                    {Vec3(2, 0, 0), tilted(26), -0.001, 3}};
  const ReducedContacts reduced = reduceContacts(candidates);
  ASSERT_EQ(reduced.clusterCount, 2);
  EXPECT_EQ(selectedIds(reduced, candidates, 0), (std::vector<int>{1, 2}));
  EXPECT_EQ(selectedIds(reduced, candidates, 1), (std::vector<int>{3}));
}

TEST(ContactReduction, HysteresisKeepsThePointsUnderJitter) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-1e-6, 1e-6);  // m: 0.1% of the depth, 0.01% of the spacing
  auto jittered = [&]() {
    std::vector<ContactCandidate> patch = flatPatch(0.001);
    for (ContactCandidate& c : patch) {
      c.distance += jitter(rng);
      c.position += Vec3(jitter(rng), jitter(rng), jitter(rng));
    }
    return patch;
  };
  std::vector<ContactCandidate> patch = jittered();
  const std::vector<SelectedContactPoint> first = reduceContacts(patch).selectedPoints(patch);
  std::vector<SelectedContactPoint> previous = first;
  int changedWithout = 0;
  ContactReductionSettings without;
  without.hysteresis = 0.0;
  for (int step = 0; step < 50; ++step) {
    patch = jittered();
    const std::vector<SelectedContactPoint> kept = reduceContacts(patch, {}, previous).selectedPoints(patch);
    EXPECT_EQ(ids(kept), ids(first)) << step;
    previous = kept;
    changedWithout += ids(reduceContacts(patch, without, first).selectedPoints(patch)) != ids(first);
  }
  EXPECT_GT(changedWithout, 10);  // without hysteresis the deepest point hops around
}

TEST(ContactReduction, AtMostFourCandidatesAreAllKept) {
  for (int n = 1; n <= 4; ++n) {
    std::vector<ContactCandidate> candidates;
    for (int i = 0; i < n; ++i) candidates.push_back({Vec3(i, i * i, 0), Vec3::UnitZ(), -0.001 * i, 10 - i});
    const ReducedContacts reduced = reduceContacts(candidates);
    ASSERT_EQ(reduced.clusterCount, 1);
    EXPECT_EQ(reduced.clusters[0].selectedCount, n);
    EXPECT_EQ(candidates[reduced.clusters[0].selected[0]].point, 10 - (n - 1));  // deepest first
  }
  // Four opposed normals: four clusters of one.
  const std::vector<ContactCandidate> opposed = {{Vec3::Zero(), Vec3::UnitX(), 0, 0},
                                                 {Vec3::Zero(), -Vec3::UnitX(), 0, 1},
                                                 {Vec3::Zero(), Vec3::UnitY(), 0, 2},
                                                 {Vec3::Zero(), -Vec3::UnitY(), 0, 3}};
  const ReducedContacts reduced = reduceContacts(opposed);
  EXPECT_EQ(reduced.clusterCount, 4);
  EXPECT_EQ(ids(reduced.selectedPoints(opposed)), (std::vector<int>{0, 1, 2, 3}));
}

TEST(ContactReduction, LeftoversJoinTheNearestCluster) {
  // Four directions at least 53 degrees apart seed four clusters; the fifth, +x (the shallowest, so visited
  // last), is more than 25 degrees from every seed and joins the nearest: (0.6, 0, 0.8) of id 0 (53 degrees).
  const std::vector<ContactCandidate> candidates = {{Vec3::Zero(), Vec3(0.6, 0, 0.8), -0.5, 0},
                                                    {Vec3::Zero(), -Vec3::UnitX(), -0.4, 1},
                                                    {Vec3::Zero(), Vec3::UnitY(), -0.3, 2},
                                                    {Vec3::Zero(), -Vec3::UnitY(), -0.2, 3},
                                                    {Vec3::Zero(), Vec3::UnitX(), -0.1, 4}};
  const ReducedContacts reduced = reduceContacts(candidates);
  ASSERT_EQ(reduced.clusterCount, 4);
  EXPECT_EQ(reduced.clusters[0].memberCount, 2);
  EXPECT_EQ(selectedIds(reduced, candidates, 0), (std::vector<int>{0, 4}));
  EXPECT_EQ(reduced.selectedPoints(candidates).size(), 5u);
}

TEST(ContactReduction, EmptyInputGivesNoClustersAndOrderDoesNotMatter) {
  EXPECT_EQ(reduceContacts({}).clusterCount, 0);
  std::vector<ContactCandidate> patch = flatPatch(0.001);
  patch[17].distance = -0.003;
  const std::vector<int> expected = ids(reduceContacts(patch).selectedPoints(patch));
  std::mt19937 rng(3);
  for (int k = 0; k < 5; ++k) {
    std::shuffle(patch.begin(), patch.end(), rng);
    EXPECT_EQ(ids(reduceContacts(patch).selectedPoints(patch)), expected);
  }
}

TEST(ContactReduction, BadInputIsRefusedInOneLine) {
  const std::vector<ContactCandidate> patch = flatPatch(0.001);
  ContactReductionSettings settings;
  settings.maxClusters = 0;
  EXPECT_THROW(reduceContacts(patch, settings), Error);
  settings = {};
  settings.hysteresis = -0.1;
  EXPECT_THROW(reduceContacts(patch, settings), Error);
  settings = {};
  settings.clusterCosine = std::nan("");
  EXPECT_THROW(reduceContacts(patch, settings), Error);
  EXPECT_THROW(reduceContacts(patch, {}, {{5, 0}, {3, 1}}), Error);
  std::vector<ContactCandidate> bad = patch;
  bad[3].distance = std::nan("");
  EXPECT_THROW(reduceContacts(bad), Error);
}

}  // namespace
}  // namespace sdfccd
