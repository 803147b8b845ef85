/// @file
/// @brief Rigid CCD's earliest-only query (time of impact and the points tied at it, branch and bound): equal,
/// bit for bit, to the minimum of the full linear contacts on random grid fields and analytic fields, with and
/// without the tree, threaded, and with one witness contact.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/ccd/rigid_ccd_test_util.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"

namespace sdfccd {
namespace {

using namespace test;  // rigid_ccd_test_util.h and the shell helpers

// earliestOnly: the full linear query's contacts at its minimum fraction (sorted by point, as the full ones).
RigidCcdResult earliestOf(const RigidCcdResult& full) {
  RigidCcdResult expected;
  expected.firstFraction = full.firstFraction;
  for (const auto& c : full.contacts) {
    if (c.fraction == full.firstFraction) expected.contacts.push_back(c);
  }
  return expected;
}

// Earliest-only tree, linear and threaded tree all equal the minimum of the full linear contacts, bit for bit.
// Returns the full linear result.
template <class Field>
RigidCcdResult checkEarliest(const PointTree& tree, const Field& field, const Rigid& a, const Rigid& b,
                             RigidCcdSettings s, const std::string& what) {
  s.earliestOnly = false;
  s.useTree = false;
  s.threads = 1;
  const RigidCcdResult full = run(tree, field, a, b, s);
  const RigidCcdResult expected = earliestOf(full);
  EXPECT_EQ(full.contacts.empty(), expected.contacts.empty()) << what;
  s.earliestOnly = true;
  expectSameContacts(expected, run(tree, field, a, b, s), what + " earliest linear");
  s.useTree = true;
  const RigidCcdResult treeResult = run(tree, field, a, b, s);
  expectSameContacts(expected, treeResult, what + " earliest tree");
  // Each node is tested at most once by the search and once by its pass for points starting inside.
  EXPECT_LE(treeResult.stats.segmentQueries, full.stats.segmentQueries + 2 * tree.nodeCount()) << what;
  s.threads = 2;
  expectSameContacts(expected, run(tree, field, a, b, s), what + " earliest tree, 2 threads");
  // earliestOneContact: the same fraction, bit for bit, and exactly one of the tied contacts.
  s.earliestOneContact = true;
  for (const bool useTree : {false, true}) {
    s.useTree = useTree;
    const std::string label = what + (useTree ? " one contact, tree" : " one contact, linear");
    const RigidCcdResult one = run(tree, field, a, b, s);
    EXPECT_EQ(one.firstFraction, expected.firstFraction) << label;
    EXPECT_EQ(one.contacts.size(), expected.contacts.empty() ? 0u : 1u) << label;
    if (one.contacts.size() != 1 || expected.contacts.empty()) continue;
    const auto tied = std::find_if(expected.contacts.begin(), expected.contacts.end(),
                                   [&](const PointContact& c) { return c.point == one.contacts[0].point; });
    EXPECT_NE(tied, expected.contacts.end()) << label << ": the witness is not one of the earliest contacts";
    if (tied == expected.contacts.end()) continue;
    RigidCcdResult witness;
    witness.contacts.push_back(*tied);
    witness.firstFraction = expected.firstFraction;
    expectSameContacts(witness, one, label);
    EXPECT_LE(one.stats.segmentQueries, treeResult.stats.segmentQueries + (useTree ? 0 : tree.pointCount())) << label;
  }
  return full;
}

TEST(RigidCcd, EarliestOnlyEqualsTheMinimumOfTheLinearContactsOnRandomGridFields) {
  std::mt19937 rng(31);
  int withContacts = 0;
  int withoutContacts = 0;
  int startsInside = 0;
  std::int64_t earliestQueries = 0;
  std::int64_t fullQueries = 0;
  for (int field = 0; field < 6; ++field) {
    const auto& [grid, tree, poses] = randomGridCase(200 + field, field, rng);
    for (int config = 0; config < 40; ++config) {
      Rigid a = test::randomPose(poses, rng);
      Rigid b = test::randomPose(poses, rng);
      if (config % 4 == 0) {  // short step (the simulation case)
        b = shortStepFrom(a, b);
      } else if (config % 4 == 1) {  // starts at the field's centre: some points start inside
        a.translation() = grid.grid().box().center();
      } else if (config % 8 == 2) {  // far from the field: no contact
        a.translation() = poses.max() + Vec3::Constant(5.0);
        b.translation() = poses.max() + Vec3(6.0, 5.0, 7.0);
      }
      RigidCcdSettings s = variedGridSettings(config);
      s.mode = config % 3 == 2 ? CcdMode::FirstHit : CcdMode::AllIntervals;
      s.method = config % 6 == 5 ? CcdMethod::Bisection : CcdMethod::Exact;
      const std::string what = "field " + std::to_string(field) + " config " + std::to_string(config);
      const RigidCcdResult full = checkEarliest(tree, grid, a, b, s, what);
      if (full.contacts.empty()) {
        ++withoutContacts;
      } else {
        ++withContacts;
      }
      for (const auto& c : full.contacts) {
        if (c.state == SegmentState::StartsInside) {
          ++startsInside;
          break;
        }
      }
      fullQueries += full.stats.segmentQueries;
      s.earliestOnly = true;
      earliestQueries += run(tree, grid, a, b, s).stats.segmentQueries;
    }
  }
  EXPECT_GT(withContacts, 50);
  EXPECT_GT(withoutContacts, 10);
  EXPECT_GT(startsInside, 20);
  EXPECT_LT(earliestQueries, fullQueries);  // branch and bound prunes
}

TEST(RigidCcd, EarliestOnlyEqualsTheMinimumOfTheLinearContactsOnAnalyticFields) {
  std::mt19937 rng(41);
  const PointTree tree(sampleBowl(600, 10));
  const SphereField sphere(Vec3(0.2, -0.1, 0.3), 0.8);
  const PlaneField plane(Vec3(0.3, 1.0, -0.2), 0.1);
  const Box3 poses(Vec3::Constant(-2.5), Vec3::Constant(2.5));
  int hits = 0;
  int inside = 0;
  for (int config = 0; config < 120; ++config) {
    const Rigid a = test::randomPose(poses, rng);
    const Rigid b = test::randomPose(poses, rng);
    RigidCcdSettings s = variedSphereSettings(config);
    // Ignored points must stay ignored in the earliest query too.
    std::vector<std::uint8_t> ignoredPoints(static_cast<std::size_t>(tree.pointCount()), 0);
    for (std::size_t p = 0; p < ignoredPoints.size(); p += 3) ignoredPoints[p] = 1;
    if (config % 5 == 4) s.ignoredPoints = &ignoredPoints;
    const std::string what = "config " + std::to_string(config);
    const RigidCcdResult r = checkEarliest(tree, sphere, a, b, s, what + " sphere");
    hits += r.contacts.empty() ? 0 : 1;
    inside += r.firstFraction == 0.0 ? 1 : 0;
    checkEarliest(tree, plane, a, b, s, what + " plane");
  }
  EXPECT_GT(hits, 40);
  EXPECT_GT(inside, 5);
  // A closed-form check: translation only onto the ground, the lowest point touches first.
  const PlaneField ground = PlaneField::ground();
  Rigid start = Rigid::Identity();
  start.translation() = Vec3(0.0, 3.0, 0.0);
  Rigid end = start;
  end.translation() = Vec3(0.0, -0.5, 0.0);
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& x : tree.shell().positions) lowest = std::min(lowest, (start * x).y());
  RigidCcdSettings s;
  s.earliestOnly = true;
  const RigidCcdResult r = run(tree, ground, start, end, s);
  ASSERT_FALSE(r.contacts.empty());
  EXPECT_NEAR(r.firstFraction, lowest / 3.5, 1e-14);
  for (const auto& c : r.contacts) EXPECT_EQ(c.fraction, r.firstFraction);
  EXPECT_LT(r.stats.segmentQueries, tree.pointCount() / 2);  // fewer than the linear query's
}

}  // namespace
}  // namespace sdfccd
