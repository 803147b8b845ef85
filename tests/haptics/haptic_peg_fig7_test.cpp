/// @file
/// @brief The peg-in-hole example with the paper's roles (Fig. 7, Section 5): the peg is the tool as a 64^3 field,
/// the hole a static shell of 6,691 points. The paper's claims, in deterministic virtual time: both methods insert
/// the peg into the matched hole; the constraint method never penetrates and refuses the shrunk hole while penalty
/// goes in (the false positive); penalty's penetration stays under half a voxel; the constraint method keeps few
/// contacts (paper: under 10) where penalty has many (paper: around 1,000 when fully inserted).
#include <gtest/gtest.h>

#include "haptics/haptic_test_scenes.h"
#include "sdfccd/haptics/haptic_session.h"

namespace sdfccd::haptics {
namespace {

HapticSessionSummary runPeg(const HapticScene& scene, HapticMethod method) {
  HapticSessionSettings s;
  s.method = method;
  s.recordTicks = false;
  const HapticSessionSummary summary = runHapticSession(scene, s).summary;
  EXPECT_EQ(summary.runaway, "");
  EXPECT_EQ(summary.error, "");
  std::printf(
      "%s %s: inserted %d progress %.5f m, max penetration %.4f cells, contacts max %d mean %.1f, "
      "blocked %lld stuck %lld failed %lld\n",
      scene.name.c_str(), toString(method), summary.inserted, summary.insertProgress, summary.maxPenetrationCells,
      summary.maxContacts, summary.meanContacts, static_cast<long long>(summary.blockedCycles),
      static_cast<long long>(summary.stuckCycles), static_cast<long long>(summary.failedCycles));
  return summary;
}

TEST(HapticPegFig7, BothMethodsInsertIntoTheMatchedHole) {
  const HapticScene scene = loadHapticScene(test::scenePath("peg-in-hole-fig7.json"));
  const HapticSessionSummary constraint = runPeg(scene, HapticMethod::Constraint);
  const HapticSessionSummary penalty = runPeg(scene, HapticMethod::Penalty);
  EXPECT_TRUE(constraint.inserted);
  EXPECT_EQ(constraint.maxPenetrationCells, 0.0);
  EXPECT_EQ(constraint.failedCycles, 0);
  EXPECT_LT(constraint.maxContacts, 10);  // paper: always under 10
  EXPECT_TRUE(penalty.inserted);
  EXPECT_LT(penalty.maxPenetrationCells, 0.5);  // paper: smaller than half a voxel
  EXPECT_GT(penalty.maxContacts, 10 * constraint.maxContacts);
}

TEST(HapticPegFig7, ConstraintRefusesTheShrunkHolePenaltyGoesIn) {
  const HapticScene scene = loadHapticScene(test::scenePath("peg-in-hole-fig7-shrunk.json"));
  const HapticSessionSummary constraint = runPeg(scene, HapticMethod::Constraint);
  const HapticSessionSummary penalty = runPeg(scene, HapticMethod::Penalty);
  EXPECT_FALSE(constraint.inserted);
  EXPECT_EQ(constraint.maxPenetrationCells, 0.0);
  EXPECT_TRUE(penalty.inserted);  // the false positive
  EXPECT_GT(penalty.maxPenetrationCells, 0.0);
}

}  // namespace
}  // namespace sdfccd::haptics
