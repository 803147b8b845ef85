// Golden determinism hash (as Box2D's test_determinism.c): a shipped scene stepped a fixed number of frames
// must end in exactly the recorded state. A refactor that changes any result, by one bit, fails here; a change
// that alters results on purpose records the new value once and says why in its commit.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "sdfccd/bullet/scene_world.h"

namespace sdfccd {
namespace {

// Paper Fig. 10a's drop, 20 bunnies with 777-point shells and 128^3 fields: by frame 600 the lower bunnies
// have hit the ground and the upper ones each other, so ground, body-body, friction and the time-of-impact
// clamp all contribute. The scene names the paper's parameters (penalty mode, per-point stiffness and damping,
// shell_normal, regularized friction); the hash also pins the rounding of the time-of-impact clamp's inelastic
// impulse (in double, in the core: time_of_impact_clamp.h) and that our impulses wake no sleeping body.
constexpr int kFrames = 600;
constexpr std::uint64_t kGoldenHash = 0xe4178163e11a2192ull;

TEST(GoldenHash, DropBunniesAfter600Frames) {
  const Scene scene = loadScene(std::string(SDFCCD_ASSETS_DIR) + "/scenes/drop-bunnies.json");
  bullet::SceneWorld world(scene);
  for (int f = 0; f < kFrames; ++f) world.step();
  char hex[32];
  std::snprintf(hex, sizeof hex, "0x%016llxull", static_cast<unsigned long long>(world.stateHash()));
  EXPECT_EQ(world.stateHash(), kGoldenHash) << "state hash after " << kFrames << " frames: " << hex;
}

}  // namespace
}  // namespace sdfccd
