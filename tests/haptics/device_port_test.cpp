/// @file
/// @brief The device port: a recorded trajectory replays row by row, bit for bit, through the loop and through a whole
/// session on a player device; an exception in the simulation loop or in the haptic loop ends the session with the
/// error reported and zero force written on the failing tick and no tick after it, in virtual time and in real time
/// (short: the real-time cases run under TSan).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "haptics/haptic_test_scenes.h"
#include "haptics_experiments/session_output.h"
#include "sdfccd/error.h"
#include "sdfccd/haptics/device_emulator.h"
#include "sdfccd/haptics/haptic_session.h"
#include "sdfccd/haptics/trajectory_player.h"
#include "sdfccd/haptics/two_loop_runner.h"
#include "session/fault_injection.h"

namespace sdfccd::haptics {
namespace {

/// A recording of `rows` samples at 1 kHz: a drift along x and z, a dip in y and a turn about a tilted axis.
std::vector<PoseKeyframe> recordedMotion(int rows) {
  std::vector<PoseKeyframe> keys;
  for (int i = 0; i < rows; ++i) {
    const double t = 0.001 * i;
    PoseKeyframe k;
    k.time = t;
    k.worldFromTarget.translation() = Vec3(0.01 * t, 0.01001 - 0.003 * std::sin(20.0 * t), 0.002 * t * t);
    k.worldFromTarget.linear() =
        Eigen::AngleAxisd(0.3 * std::sin(7.0 * t), Vec3(1, 2, 3).normalized()).toRotationMatrix();
    keys.push_back(k);
  }
  return keys;
}

/// Writes the recording as the player's CSV (17 significant digits: the numbers read back are the ones written).
std::string writeRecording(const std::vector<PoseKeyframe>& keys, const std::string& name) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::FILE* f = std::fopen(path.c_str(), "w");
  std::fprintf(f, "t,x,y,z,qw,qx,qy,qz\n");
  for (const PoseKeyframe& k : keys) {
    const Quat q(k.worldFromTarget.linear());
    const Vec3 p = k.worldFromTarget.translation();
    std::fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", k.time, p.x(), p.y(), p.z(), q.w(), q.x(),
                 q.y(), q.z());
  }
  std::fclose(f);
  return path;
}

TEST(TrajectoryPlayer, ReplaysARecordingRowByRowThroughTheLoop) {
  const std::vector<PoseKeyframe> keys = recordedMotion(300);
  const std::string path = writeRecording(keys, "player_replay.csv");
  const UserScript loaded = UserScript::loadCsv(path);  // the reference: the rows as read (quaternions normalized)
  TrajectoryPlayer player = TrajectoryPlayer::fromCsv(path, 1000.0);
  ASSERT_EQ(player.tickCount(), 300);
  std::vector<Rigid> seen;
  std::vector<Vec6> twists;
  DeviceLoop loop(player);
  const LoopTimingStats stats = loop.runVirtual(1000, [&](const DeviceState& s) {
    seen.push_back(s.body.worldFromBody);
    twists.push_back(s.body.twist());
    Vec6 w = Vec6::Zero();
    w[1] = static_cast<double>(s.tick);  // a wrench that names its tick
    return w;
  });
  EXPECT_EQ(stats.ticks, 300);  // the player ends with its recording, not at the 1000 asked for
  EXPECT_EQ(loop.error(), "");
  ASSERT_EQ(seen.size(), 300u);
  for (std::size_t i = 0; i < seen.size(); ++i) {
    ASSERT_EQ(seen[i].matrix(), loaded.keys()[i].worldFromTarget.matrix()) << "tick " << i;  // exact
    ASSERT_LT((seen[i].translation() - keys[i].worldFromTarget.translation()).norm(), 1e-15);
    if (i + 1 < seen.size()) {
      const Vec6 expected = poseDifference(seen[i], loaded.keys()[i + 1].worldFromTarget) * 1000.0;
      ASSERT_LT((twists[i] - expected).norm(), 1e-12) << "tick " << i;
    }
  }
  EXPECT_EQ(twists.back(), Vec6::Zero());
  ASSERT_EQ(player.wrenches().size(), 300u);
  for (std::size_t i = 0; i < 300; ++i) ASSERT_EQ(player.wrenches()[i][1], static_cast<double>(i));
  EXPECT_THROW(player.write(Vec6::Zero()), Error);  // past the end
  std::remove(path.c_str());
}

TEST(TrajectoryPlayer, DrivesAWholeSessionInPlaceOfTheEmulator) {
  // The plane-slide box, its device replaced by a recorded hand motion that dips 3 mm into the plane.
  const HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  const std::vector<PoseKeyframe> keys = recordedMotion(400);
  TrajectoryPlayer player(UserScript(keys), scene.device.rateHz);
  HapticSessionSettings settings;
  settings.method = HapticMethod::Constraint;
  settings.seconds = 1.0;  // longer than the recording: the session ends with it
  const HapticSessionResult r = runHapticSession(scene, settings, player);
  EXPECT_EQ(r.summary.error, "");
  ASSERT_EQ(r.ticks.size(), 400u);
  for (std::size_t i = 0; i < r.ticks.size(); ++i)
    ASSERT_EQ(r.ticks[i].worldFromDevice.matrix(), keys[i].worldFromTarget.matrix()) << "tick " << i;
  EXPECT_EQ(r.summary.maxPenetrationCells, 0.0);
  // The device was pushed into the plane: the god-object held it back with an upward force, written to the player.
  double maxUp = 0.0;
  for (const Vec6& w : player.wrenches()) maxUp = std::max(maxUp, w[1]);
  EXPECT_GT(maxUp, 0.1);
  ASSERT_EQ(player.wrenches().size(), 400u);
  for (std::size_t i = 0; i < 400; ++i) ASSERT_EQ(player.wrenches()[i], r.ticks[i].wrenchOnDevice);
  EXPECT_THROW(TrajectoryPlayer(UserScript(keys), 0.0), Error);
}

/// Runs `scene` on its own emulator with a fault injected (the session's internal seam, fault_injection.h); returns the
/// result, the emulator's final state in `last`.
HapticSessionResult runWithFault(const HapticScene& scene, HapticSessionSettings settings, const SessionFaults& faults,
                                 DeviceState& last) {
  DeviceEmulator device(scene.device, scene.script, scene.worldFromBodyStart);
  settings.recordTicks = true;
  HapticSessionResult r = runHapticSessionWithFaults(scene, settings, device, faults);
  last = device.state();
  return r;
}

TEST(TwoLoopRunner, ASimulationExceptionEndsTheSessionWithZeroForce) {
  const HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  HapticSessionSettings s;
  s.method = HapticMethod::Constraint;
  s.seconds = 0.6;
  SessionFaults faults;
  faults.simulationCycle = 450;  // pressing into the plane by then
  DeviceState last;
  const HapticSessionResult r = runWithFault(scene, s, faults, last);
  EXPECT_NE(r.summary.error.find("simulation loop: injected fault at simulation cycle 450"), std::string::npos)
      << r.summary.error;
  // Ticks 0..449 ran; tick 450 failed in its simulation cycle, wrote zero, and the loop ended.
  EXPECT_EQ(r.summary.hapticTicks, 451);
  ASSERT_EQ(r.ticks.size(), 450u);
  EXPECT_GT(r.ticks.back().wrenchOnDevice.head<3>().norm(), 0.1);  // it was rendering a force
  EXPECT_EQ(last.tick, 451);
  EXPECT_EQ(last.renderedWrench, Vec6::Zero());
  EXPECT_NE(summaryJson(r.summary).find("\"error\": \"simulation loop: injected fault"), std::string::npos);
}

TEST(TwoLoopRunner, AHapticTickExceptionEndsThePenaltySessionWithZeroForce) {
  const HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  HapticSessionSettings s;
  s.method = HapticMethod::Penalty;
  s.seconds = 0.6;
  SessionFaults faults;
  faults.hapticTick = 300;
  DeviceState last;
  const HapticSessionResult r = runWithFault(scene, s, faults, last);
  EXPECT_NE(r.summary.error.find("haptic loop: injected fault at haptic tick 300"), std::string::npos)
      << r.summary.error;
  EXPECT_EQ(r.summary.hapticTicks, 301);
  ASSERT_EQ(r.ticks.size(), 300u);
  EXPECT_GT(r.ticks.back().wrenchOnDevice.head<3>().norm(), 0.1);
  EXPECT_EQ(last.tick, 301);
  EXPECT_EQ(last.renderedWrench, Vec6::Zero());
}

TEST(TwoLoopRunner, RealTimeSurvivesAnExceptionInEitherLoop) {
  // Short real-time runs (threads: the TSan stage runs them). The failing tick's number depends on the scheduling;
  // what must hold is the clean end: the error named, zero force on the last tick, both loops joined.
  const HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  for (const HapticMethod method : {HapticMethod::Constraint, HapticMethod::Penalty}) {
    HapticSessionSettings s;
    s.method = method;
    s.realTime = true;
    s.seconds = 0.3;
    SessionFaults faults;
    if (method == HapticMethod::Constraint)
      faults.simulationCycle = 40;
    else
      faults.hapticTick = 40;
    DeviceState last;
    const HapticSessionResult r = runWithFault(scene, s, faults, last);
    const char* loop = method == HapticMethod::Constraint ? "simulation loop: injected" : "haptic loop: injected";
    EXPECT_NE(r.summary.error.find(loop), std::string::npos) << r.summary.error;
    EXPECT_LT(r.summary.hapticTicks, 300);
    EXPECT_EQ(last.tick, r.summary.hapticTicks);
    EXPECT_EQ(last.renderedWrench, Vec6::Zero());
    EXPECT_EQ(r.summary.realTimePriority, "off");  // never asked for in the tests
  }
}

TEST(TwoLoopRunner, ALoopThatCannotStartIsAnErrorNotATermination) {
  // Real time with a simulation thread already running when the device loop refuses its options (priority outside
  // 1..99): the runner joins the thread and rethrows; the test process survives (std::terminate would end it).
  TrajectoryPlayer player(UserScript(recordedMotion(100)), 1000.0);
  TwoLoopSettings settings;
  settings.ticks = 10;
  settings.realTime = true;
  settings.loop.realTimePriority = true;
  settings.loop.priority = 0;
  TwoLoopRunner runner(player, settings);
  std::atomic<std::int64_t> cycles{0};
  EXPECT_THROW(runner.run(
                   [&](const DeviceState&) {
                     ++cycles;
                     return false;
                   },
                   [](const DeviceState&) { return Vec6::Zero().eval(); }),
               Error);
  EXPECT_TRUE(player.wrenches().empty());
}

TEST(TwoLoopRunner, RunsAnyDeviceAndStopsOnRequest) {
  TrajectoryPlayer player(UserScript(recordedMotion(100)), 1000.0);
  TwoLoopSettings settings;
  settings.ticks = 1000;
  settings.simCyclesPerTick = 3;
  TwoLoopRunner runner(player, settings);
  std::int64_t cycles = 0;
  const TwoLoopResult r = runner.run(
      [&](const DeviceState&) {
        ++cycles;
        return true;
      },
      [&](const DeviceState& state) {
        if (state.tick == 49) runner.requestStop();
        return Vec6::Constant(1.0);
      });
  EXPECT_EQ(r.error, "");
  EXPECT_EQ(r.timing.ticks, 50);
  EXPECT_EQ(r.simulationCycles, 150);
  EXPECT_EQ(cycles, 150);
  EXPECT_EQ(player.wrenches().size(), 50u);
  TwoLoopSettings bad;
  bad.ticks = -1;
  EXPECT_THROW(TwoLoopRunner(player, bad), Error);
}

}  // namespace
}  // namespace sdfccd::haptics
