/// @file
/// @brief rigidCcdCertifiedClear (rigid_ccd.h): the coherent query's whole-front fast path. Wherever it answers
/// "no contact possible", the fresh query must find no contact; wherever it declines, the coherent query must
/// return the fresh query's contacts bit for bit. Each test also checks that the fast path fired (a dead fast
/// path passes nothing) and that contacts occurred (a test that never touches proves nothing).
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "core/ccd/rigid_ccd_test_util.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/ccd/rigid_ccd_coherence.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"

namespace sdfccd {
namespace {

struct ClearCounts {
  int clear = 0;     // steps the fast path answered
  int contacts = 0;  // contacts the fresh query found over all steps
};

/// One step: the fast path first; when it answers, the fresh query must be empty; else the coherent query runs
/// and must equal the fresh one.
void clearOrCoherentStep(const PointTree& tree, const GridField& field, const Rigid& a, const Rigid& b,
                         const RigidCcdSettings& s, RigidCcdCoherence& history, const std::string& what,
                         ClearCounts& counts) {
  RigidCcdResult fresh;
  rigidCcd(tree, field, a, b, s, fresh);
  counts.contacts += static_cast<int>(fresh.contacts.size());
  RigidCcdResult coherent;
  coherent.contacts.emplace_back();  // must be cleared by either path
  if (rigidCcdCertifiedClear(tree, field, a, b, s, history, coherent)) {
    ++counts.clear;
    EXPECT_TRUE(fresh.contacts.empty()) << what << ": certified clear, but the fresh query touches";
    EXPECT_TRUE(coherent.contacts.empty()) << what;
    EXPECT_EQ(coherent.firstFraction, 1.0) << what;
    EXPECT_EQ(coherent.stats.certified, static_cast<std::int64_t>(history.frontSize())) << what;
    return;
  }
  rigidCcd(tree, field, a, b, s, history, coherent);
  test::expectSameContacts(fresh, coherent, what);
}

/// A small random step from `pose` (rotation and translation of about `size`).
Rigid randomStep(const Rigid& pose, double size, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, 1.0);
  Rigid next = pose;
  next.translation() += size * Vec3(noise(rng), noise(rng), noise(rng));
  next.linear() = pose.linear() * Eigen::AngleAxisd(size * noise(rng), Vec3::UnitZ()).toRotationMatrix() *
                  Eigen::AngleAxisd(size * noise(rng), Vec3::UnitY()).toRotationMatrix();
  return next;
}

TEST(RigidCcdCertifiedClear, RandomWalksNearTheFieldClearOnlyWithoutContact) {
  std::mt19937 rng(23);
  ClearCounts counts;
  for (int field = 0; field < 6; ++field) {
    const test::RandomGridCase c = test::randomGridCase(300 + field, field, rng);
    const RigidCcdSettings s = test::variedGridSettings(field);
    RigidCcdCoherence history;
    // Start around the box's surface, so that the walk goes in and out of contact; tiny steps (a resting pile)
    // with a larger one now and then (the certificates must then fail).
    const Box3 box = c.grid.grid().box();
    Rigid pose = test::randomPose(test::expanded(box, 1.6), rng);
    for (int step = 0; step < 300; ++step) {
      const double size = step % 23 == 0 ? 0.2 : (step % 5 == 0 ? 0.01 : 0.001);
      Rigid next = randomStep(pose, size * box.sizes().maxCoeff(), rng);
      if (step % 7 == 3) {  // a turn in place (the rotation alone must break the certificates)
        next.translation() = pose.translation();
        next.linear() = pose.linear() * Eigen::AngleAxisd(0.3, Vec3::UnitX()).toRotationMatrix();
      }
      if (!test::expanded(box, 2.0).contains(next.translation())) next.translation() = box.center();
      clearOrCoherentStep(c.tree, c.grid, pose, next, s, history,
                          "field " + std::to_string(field) + " step " + std::to_string(step), counts);
      pose = next;
    }
  }
  EXPECT_GT(counts.clear, 20);  // 57 with these seeds
  EXPECT_GT(counts.contacts, 1000);
}

TEST(RigidCcdCertifiedClear, AStepIntoContactIsNeverClear) {
  std::mt19937 rng(31);
  const test::RandomGridCase c = test::randomGridCase(41, 0, rng);
  const RigidCcdSettings s;
  // A pose where the shell touches the field, and one outside it by a gap of 1.5 field sizes (certified at
  // rest; a node culled by its segment test with a clearance under its radius is never certified, so a pair
  // at rest just apart keeps re-testing such nodes: the fast path needs the wider gap).
  Rigid near = test::randomPose(c.grid.grid().box(), rng);
  for (int tries = 0; tries < 100 && test::run(c.tree, c.grid, near, near, s).contacts.empty(); ++tries) {
    near = test::randomPose(c.grid.grid().box(), rng);
  }
  ASSERT_FALSE(test::run(c.tree, c.grid, near, near, s).contacts.empty());
  Rigid apart = near;
  const double size = c.grid.grid().box().sizes().maxCoeff();
  while (!test::run(c.tree, c.grid, apart, apart, s).contacts.empty()) apart.translation().x() += 0.05 * size;
  apart.translation().x() += 1.5 * size;  // a gap wider than the tree's upper nodes, so that they certify
  RigidCcdCoherence history;
  ClearCounts counts;
  for (int k = 0; k < 4; ++k) clearOrCoherentStep(c.tree, c.grid, apart, apart, s, history, "apart", counts);
  EXPECT_GE(counts.clear, 2) << "at rest apart, the certificates should answer alone";
  RigidCcdResult out;
  EXPECT_FALSE(rigidCcdCertifiedClear(c.tree, c.grid, apart, near, s, history, out));
  clearOrCoherentStep(c.tree, c.grid, apart, near, s, history, "into contact", counts);
  EXPECT_GT(counts.contacts, 0);
}

TEST(RigidCcdCertifiedClear, QueriesWithoutHistoryUseNeverClear) {
  std::mt19937 rng(37);
  const test::RandomGridCase c = test::randomGridCase(43, 0, rng);
  Rigid far = Rigid::Identity();
  far.translation() = Vec3(100.0, 0.0, 0.0);
  RigidCcdSettings s;
  RigidCcdCoherence history;
  RigidCcdResult out;
  EXPECT_FALSE(rigidCcdCertifiedClear(c.tree, c.grid, far, far, s, history, out));  // no history yet
  rigidCcd(c.tree, c.grid, far, far, s, history, out);
  EXPECT_TRUE(rigidCcdCertifiedClear(c.tree, c.grid, far, far, s, history, out));
  // What the coherent query does not cover: earliest contact, a culling override, the linear traversal,
  // another sigma, and a field without an instance id.
  RigidCcdSettings other = s;
  other.earliestOnly = true;
  EXPECT_FALSE(rigidCcdCertifiedClear(c.tree, c.grid, far, far, other, history, out));
  other = s;
  other.cullLipschitz = 1.0;
  EXPECT_FALSE(rigidCcdCertifiedClear(c.tree, c.grid, far, far, other, history, out));
  other = s;
  other.useTree = false;
  EXPECT_FALSE(rigidCcdCertifiedClear(c.tree, c.grid, far, far, other, history, out));
  other = s;
  other.sigma = 0.01;
  EXPECT_FALSE(rigidCcdCertifiedClear(c.tree, c.grid, far, far, other, history, out));
  const PlaneField plane(Vec3::UnitY(), 0.0);
  EXPECT_FALSE(rigidCcdCertifiedClear(c.tree, plane, far, far, s, history, out));
  // A non-finite pose is left to the full query, which reports it.
  Rigid bad = far;
  bad.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(rigidCcdCertifiedClear(c.tree, c.grid, far, bad, s, history, out));
}

}  // namespace
}  // namespace sdfccd
