/// @file
/// @brief The god-object's clearance cache (god_object.h): skipping the points that provably cannot reach sigma
/// changes nothing (bit-identical poses, fractions and contacts with the cache off) and saves segment queries,
/// on the peg in the matched hole (a tight fit: every side point within 0.07 voxel of the wall) and the alpha
/// puzzle's test variant (sliding along a bent tube, with rotation).
#include <gtest/gtest.h>

#include <string>

#include "haptics/haptic_test_scenes.h"
#include "sdfccd/haptics/god_object.h"
#include "sdfccd/haptics/haptic_scene.h"

namespace sdfccd::haptics {
namespace {

// Drives two god-objects (cache on / off) with the scripted target directly (no device), and compares them.
void expectCacheChangesNothing(const std::string& sceneFile, double seconds) {
  const HapticScene scene = loadHapticScene(test::scenePath(sceneFile));
  GodObjectSettings on = scene.god;
  on.clearanceCache = true;
  GodObjectSettings off = scene.god;
  off.clearanceCache = false;
  GodObject cached(ObstacleContacts(*scene.tree, *scene.grid, scene.worldFromSdf), scene.worldFromBodyStart, on);
  GodObject plain(ObstacleContacts(*scene.tree, *scene.grid, scene.worldFromSdf), scene.worldFromBodyStart, off);
  std::int64_t cachedQueries = 0, plainQueries = 0;
  int contactCycles = 0;
  const int cycles = static_cast<int>(seconds * 1000.0);
  for (int k = 0; k < cycles; ++k) {
    const Rigid target = scene.script.targetAt(1e-3 * k);
    const GodObjectStepResult a = cached.step(target);
    const GodObjectStepResult b = plain.step(target);
    ASSERT_EQ(a.fraction, b.fraction) << sceneFile << " cycle " << k;
    ASSERT_EQ(a.nextContactCount, b.nextContactCount) << sceneFile << " cycle " << k;
    ASSERT_TRUE(cached.pose().matrix() == plain.pose().matrix()) << sceneFile << " cycle " << k;
    for (std::size_t c = 0; c < cached.contacts().size(); ++c)
      ASSERT_EQ(cached.contacts()[c].point, plain.contacts()[c].point) << sceneFile << " cycle " << k;
    cachedQueries += a.segmentQueries;
    plainQueries += b.segmentQueries;
    contactCycles += a.nextContactCount > 0;
  }
  EXPECT_GT(contactCycles, cycles / 4) << sceneFile;  // the comparison covered contact, not only free motion
  EXPECT_LT(cachedQueries, plainQueries / 2) << sceneFile;
}

TEST(GodObjectClearanceCache, BitIdenticalInTheTightPegFit) {
  expectCacheChangesNothing("peg-in-hole.json", 2.2);
}

TEST(GodObjectClearanceCache, BitIdenticalSlidingAlongTheAlphaTube) {
  expectCacheChangesNothing("alpha-puzzle-small.json", 3.5);
}

}  // namespace
}  // namespace sdfccd::haptics
