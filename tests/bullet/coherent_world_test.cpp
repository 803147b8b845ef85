// The CCD history (ContactSettings::coherentCcd: each pair and role's query starts from its last front,
// and answers from its certificates alone when they rule out every contact) must not change a simulation by one
// bit: a small pile of bunnies stepped with and without it ends in the same state, in penalty and in solver mode.
// The pile is dense enough that pairs overlap in the broadphase without touching (the certificates' case) and
// bodies rest on each other (the fronts' case).
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "sdfccd/bullet/scene_world.h"

namespace sdfccd {
namespace {

/// drop-bunnies' lower layer's first four bunnies and the four of the upper layer above them.
Scene coherentWorldPile(SdfccdContactMode mode, double timestep) {
  Scene scene = loadScene(std::string(SDFCCD_ASSETS_DIR) + "/scenes/drop-bunnies.json");
  const std::vector<SceneBody> all = scene.bodies;
  scene.bodies = {all[0], all[1], all[5], all[6], all[10], all[11], all[15], all[16]};
  scene.contact = SceneContact{};
  scene.contact.mode = mode;
  scene.timestep = timestep;
  return scene;
}

struct CoherentWorldRun {
  std::uint64_t hash = 0;
  std::int64_t contacts = 0;  // shell points in contact, summed over the frames
};

CoherentWorldRun runCoherentWorldPile(const Scene& scene, int frames, bool coherent) {
  bullet::SceneWorldSettings settings;
  settings.cacheDir = ::testing::TempDir() + "sdfccd_coherent_world_cache";  // the field is built once
  settings.coherentCcd = coherent;
  bullet::SceneWorld world(scene, settings);
  CoherentWorldRun run;
  for (int f = 0; f < frames; ++f) {
    world.step();
    run.contacts += world.lastFrame().contacts;
  }
  run.hash = world.stateHash();
  return run;
}

TEST(CoherentWorld, PenaltyPileEndsInTheFreshQuerysState) {
  const Scene scene = coherentWorldPile(SdfccdContactMode::Penalty, 0.001);
  const CoherentWorldRun fresh = runCoherentWorldPile(scene, 450, false);
  const CoherentWorldRun coherent = runCoherentWorldPile(scene, 450, true);
  EXPECT_GT(fresh.contacts, 1000);
  EXPECT_EQ(coherent.contacts, fresh.contacts);
  EXPECT_EQ(coherent.hash, fresh.hash);
}

TEST(CoherentWorld, SolverPileEndsInTheFreshQuerysState) {
  const Scene scene = coherentWorldPile(SdfccdContactMode::Solver, 1.0 / 240.0);
  const CoherentWorldRun fresh = runCoherentWorldPile(scene, 150, false);
  const CoherentWorldRun coherent = runCoherentWorldPile(scene, 150, true);
  EXPECT_GT(fresh.contacts, 100);
  EXPECT_EQ(coherent.contacts, fresh.contacts);
  EXPECT_EQ(coherent.hash, fresh.hash);
}

}  // namespace
}  // namespace sdfccd
