/// @file
/// @brief Passivity on the device port: the force-rate limit ramps a step by exactly its limit; Colgate's bound; a
/// sampled stiff wall pushed for 10 s (virtual time) gains energy without the controller and never more than the stated
/// bound with it, at Colgate's limit and at 10 times it; the same through a whole constraint-method session on a plane
/// rendered at those stiffnesses.
#include "sdfccd/haptics/passivity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "haptics/haptic_test_scenes.h"
#include "sdfccd/error.h"
#include "sdfccd/haptics/device_emulator.h"
#include "sdfccd/haptics/haptic_session.h"
#include "sdfccd/haptics/two_loop_runner.h"

namespace sdfccd::haptics {
namespace {

TEST(PassivityController, RateLimitRampsAStepByItsLimitPerTick) {
  PassivitySettings p;
  p.controller = false;
  p.maxForceStep = 0.5;
  p.maxTorqueStep = 0.01;
  PassivityController pc(p);
  DeviceState still;
  Vec6 step = Vec6::Zero();
  step.head<3>() = Vec3(0, 3, 4);  // 5 N
  step[5] = 0.03;
  for (int n = 1; n <= 12; ++n) {
    still.tick = n;
    const Vec6 out = pc.filter(still, step);
    EXPECT_NEAR(out.head<3>().norm(), std::min(5.0, 0.5 * n), 1e-12) << n;
    EXPECT_TRUE(out.head<3>().normalized().isApprox(Vec3(0, 0.6, 0.8)));
    EXPECT_NEAR(out[5], std::min(0.03, 0.01 * n), 1e-12);
  }
  EXPECT_NEAR(pc.stats().maxForceStep, 0.5, 1e-12);
  // Ticks 1..9 are limited; tick 10 closes the last 0.5 N, limited or not by rounding.
  EXPECT_GE(pc.stats().rateLimitedTicks, 9);
  EXPECT_LE(pc.stats().rateLimitedTicks, 10);
  PassivitySettings bad;
  bad.maxForceStep = -1.0;
  EXPECT_THROW(PassivityController{bad}, Error);
}

TEST(PassivityController, ColgateBound) {
  EXPECT_DOUBLE_EQ(colgateMaxStiffness(9.0, 1e-3), 1.8e4);  // the emulated device: friction 1 + hand 8 N s/m
  EXPECT_DOUBLE_EQ(colgateMaxStiffness(9.0, 1e-3, 4.0), 1.0e4);
  EXPECT_EQ(colgateMaxStiffness(1.0, 1e-3, 2.0), 0.0);
}

/// 10 s of a scripted hand pushing the emulated device into a wall at y = 0 and letting go, twice a second.
UserScript pushingScript() {
  std::vector<PoseKeyframe> keys;
  for (int i = 0; i <= 40; ++i) {
    PoseKeyframe k;
    k.time = 0.25 * i;
    k.worldFromTarget.translation() = Vec3(0.0, i % 2 == 0 ? 0.004 : -0.006, 0.0);
    keys.push_back(k);
  }
  return UserScript(keys);
}

struct WallRun {
  PassivityStats stats;
  double energy = 0.0;     // J, -sum F . dx recomputed from the written wrenches and the device's poses
  double minEnergy = 0.0;  // J
};

/// A sampled wall (zero-order hold: F = K max(0, -y) from the pose at the tick's start) on the emulator, pushed for
/// 10 s in virtual time; the controller on or off.
WallRun pushWall(double stiffness, bool controller) {
  DeviceSettings device;  // b = 1 + 8 N s/m
  DeviceEmulator emulator(device, pushingScript(), Rigid(Eigen::Translation3d(0.0, 0.004, 0.0)));
  PassivitySettings p = HapticSessionSettings::defaultSessionPassivity();  // 1 N per tick
  p.controller = controller;
  p.maxForce = device.maxForce;
  p.maxTorque = device.maxTorque;
  PassivityController pc(p);
  TwoLoopSettings loop;
  loop.ticks = 10000;
  TwoLoopRunner runner(emulator, loop);
  WallRun run;
  Rigid lastPose = emulator.state().body.worldFromBody;
  Vec6 lastWrench = Vec6::Zero();
  const TwoLoopResult r = runner.run(nullptr, [&](const DeviceState& s) {
    run.energy -= lastWrench.dot(poseDifference(lastPose, s.body.worldFromBody));
    run.minEnergy = std::min(run.minEnergy, run.energy);
    Vec6 wall = Vec6::Zero();
    wall[1] = stiffness * std::max(0.0, -s.body.worldFromBody.translation().y());
    lastWrench = pc.filter(s, wall);
    lastPose = s.body.worldFromBody;
    return lastWrench;
  });
  EXPECT_EQ(r.error, "");
  EXPECT_EQ(r.timing.ticks, 10000);
  run.stats = pc.stats();
  return run;
}

TEST(PassivityController, SampledStiffWallNeverGainsEnergyBeyondTheBound) {
  const double limit = colgateMaxStiffness(9.0, 1e-3);
  for (const double k : {limit, 10.0 * limit}) {
    const WallRun off = pushWall(k, false);
    const WallRun on = pushWall(k, true);
    // The observer's account is the port's energy, recomputed independently.
    EXPECT_NEAR(on.stats.energy, on.energy, 1e-12);
    EXPECT_NEAR(on.stats.minEnergy, on.minEnergy, 1e-12);
    // Without the controller the sampled, rate-limited wall generates energy (measured: 5.4 mJ at Colgate's limit,
    // 0.82 J at 10 times it; the device's own damping must absorb it).
    EXPECT_LT(off.minEnergy, -5e-3) << k;
    // With it: the stated bound holds on every tick, and the gain is at least 100 times smaller (measured: 13 uJ
    // and 1.1 mJ over the 10 s).
    EXPECT_GE(on.minEnergy, -on.stats.deficitBound - 1e-15) << k;
    EXPECT_GT(on.stats.controlledTicks, 0);
    EXPECT_GT(on.minEnergy, 0.01 * off.minEnergy) << k;
    if (k <= limit) {
      EXPECT_GT(on.minEnergy, -1e-4);
    }
    RecordProperty("wall_k_" + std::to_string(int(k)) + "_min_energy_off_J", std::to_string(off.minEnergy));
    RecordProperty("wall_k_" + std::to_string(int(k)) + "_min_energy_on_J", std::to_string(on.minEnergy));
    RecordProperty("wall_k_" + std::to_string(int(k)) + "_deficit_bound_J", std::to_string(on.stats.deficitBound));
  }
}

/// The plane-slide box pushed into the plane for 10 s by the scripted hand, the god-object rendering the plane at
/// `renderStiffness`; passivity on or off.
HapticSessionSummary pushPlane(double renderStiffness, bool passivity) {
  HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  resampleSceneShell(scene, 200);  // a wall needs few points; 10 s stay short under the thread sanitizer
  std::vector<PoseKeyframe> keys;
  for (int i = 0; i <= 40; ++i) {
    PoseKeyframe k;
    k.time = 0.25 * i;
    k.worldFromTarget.translation() = Vec3(0.0, i % 2 == 0 ? 0.012 : 0.004, 0.0);  // the box's bottom at y - 0.01
    keys.push_back(k);
  }
  scene.script = UserScript(keys);
  scene.god.renderStiffness = renderStiffness;
  HapticSessionSettings s;
  s.method = HapticMethod::Constraint;
  s.seconds = 10.0;
  s.recordTicks = false;
  s.passivityEnabled = passivity;
  return runHapticSession(scene, s).summary;
}

TEST(PassivityController, ConstraintSessionOnAStiffPlaneNeverGainsEnergyBeyondTheBound) {
  const double limit = colgateMaxStiffness(9.0, 1e-3);
  for (const double k : {limit, 10.0 * limit}) {
    const HapticSessionSummary on = pushPlane(k, true);
    EXPECT_EQ(on.error, "");
    EXPECT_EQ(on.maxPenetrationCells, 0.0);
    EXPECT_GE(on.passivity.minEnergy, -on.passivity.deficitBound - 1e-15) << k;
    EXPECT_DOUBLE_EQ(on.colgateMaxStiffness, limit);
    const HapticSessionSummary off = pushPlane(k, false);
    std::printf(
        "plane k %g: port energy min with passivity %.3g J (bound %.3g J, controlled ticks %lld, max force step %.3g "
        "N), without %.3g J (max force step %.3g N)\n",
        k, on.passivity.minEnergy, on.passivity.deficitBound, static_cast<long long>(on.passivity.controlledTicks),
        on.passivity.maxForceStep, off.passivity.minEnergy, off.passivity.maxForceStep);
    // Measured: 14 uJ vs 4.8 mJ at Colgate's limit, 4.0 mJ vs 0.32 J at 10 times it.
    EXPECT_GT(on.passivity.minEnergy, 0.05 * off.passivity.minEnergy) << k;
    if (k <= limit) {
      EXPECT_GT(on.passivity.minEnergy, -1e-4);
    }
  }
}

}  // namespace
}  // namespace sdfccd::haptics
