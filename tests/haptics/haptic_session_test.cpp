/// @file
/// @brief Whole haptic sessions on the shipped scenes, in deterministic virtual time (paper Sections 4, 5):
/// peg in the matched hole (both methods), the shrunk hole (constraint stops, penalty goes in: Fig. 7),
/// a fast push onto a thin wire (constraint never penetrates, discrete penalty tunnels: Figs. 11, 12),
/// a box sliding on a plane, the Fig. 13 pocket (Stuck, never NaN); the real-time two-loop mode; outputs; the
/// runaway guard: an exploding object makes the device render zero force and the loop stop.
#include "sdfccd/haptics/haptic_session.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "haptics/haptic_test_scenes.h"
#include "haptics_experiments/session_output.h"
#include "sdfccd/error.h"

namespace sdfccd::haptics {
namespace {

HapticSessionSummary run(const HapticScene& scene, HapticMethod method) {
  HapticSessionSettings s;
  s.method = method;
  s.recordTicks = false;
  const HapticSessionSummary summary = runHapticSession(scene, s).summary;
  // The shipped scenes are sound: the runaway guard never fires on them.
  EXPECT_EQ(summary.runaway, "") << scene.name << " " << toString(method);
  return summary;
}

struct ConstraintAndPenalty {
  HapticSessionSummary constraint;
  HapticSessionSummary penalty;
};

// The scene `name` run with the constraint method, then with the penalty method.
ConstraintAndPenalty runConstraintAndPenalty(const std::string& name) {
  const HapticScene scene = loadHapticScene(test::scenePath(name));
  return {run(scene, HapticMethod::Constraint), run(scene, HapticMethod::Penalty)};
}

TEST(HapticSession, PegGoesIntoTheMatchedHoleWithBothMethods) {
  const auto [constraint, penalty] = runConstraintAndPenalty("peg-in-hole.json");
  EXPECT_TRUE(constraint.inserted);
  EXPECT_EQ(constraint.maxPenetrationCells, 0.0);
  EXPECT_EQ(constraint.failedCycles, 0);
  EXPECT_TRUE(penalty.inserted);
  EXPECT_LT(penalty.maxPenetrationCells, 0.5);  // the coupling saturates at half a voxel
}

TEST(HapticSession, ShrunkHoleStopsTheConstraintMethodButNotPenalty) {
  const auto [constraint, penalty] = runConstraintAndPenalty("peg-in-hole-shrunk.json");
  EXPECT_FALSE(constraint.inserted);
  EXPECT_EQ(constraint.maxPenetrationCells, 0.0);
  EXPECT_GT(constraint.blockedCycles, 0);
  EXPECT_TRUE(penalty.inserted);                                // the paper's false positive
  EXPECT_GT(penalty.maxPenetrationCells, 0.0);                  // ... through a shallow penetration
  EXPECT_GT(penalty.maxContacts, 10 * constraint.maxContacts);  // paper: ~1,000 vs under 10
}

TEST(HapticSession, FastPushOntoAThinWire) {
  const HapticScene scene = loadHapticScene(test::scenePath("thin-wire.json"));
  const HapticSessionSummary constraint = run(scene, HapticMethod::Constraint);
  EXPECT_EQ(constraint.maxPenetrationCells, 0.0);
  EXPECT_FALSE(constraint.tunneled);
  EXPECT_GT(constraint.finalPosition.y(), 0.0);  // resting on the wire
  const HapticSessionSummary discretePenalty = run(scene, HapticMethod::DiscretePenalty);
  EXPECT_TRUE(discretePenalty.tunneled);
  const HapticSessionSummary discreteConstraint = run(scene, HapticMethod::DiscreteConstraint);
  EXPECT_GT(discreteConstraint.maxPenetrationCells, 0.1);  // Fig. 11: discrete detection lands deep inside
}

TEST(HapticSession, BoxSlidesOnAPlane) {
  const HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  ASSERT_TRUE(scene.plane.has_value());
  const HapticSessionSummary constraint = run(scene, HapticMethod::Constraint);
  EXPECT_TRUE(constraint.inserted);  // reached x >= 29 mm
  EXPECT_EQ(constraint.maxPenetrationCells, 0.0);
  EXPECT_GT(constraint.maxContacts, 0);
  EXPECT_NEAR(constraint.finalPosition.y(), 0.01001, 1e-4);
}

TEST(HapticSession, Fig13PocketReportsStuckNeverNaN) {
  const HapticScene scene = loadHapticScene(test::scenePath("fig13-locked-pocket.json"));
  HapticSessionSettings s;
  s.method = HapticMethod::Constraint;
  const HapticSessionResult r = runHapticSession(scene, s);
  EXPECT_GT(r.summary.stuckCycles, 0);
  EXPECT_EQ(r.summary.failedCycles, 0);
  EXPECT_EQ(r.summary.maxPenetrationCells, 0.0);
  EXPECT_TRUE(r.summary.finalPosition.allFinite());
  for (const HapticTickRecord& t : r.ticks) {
    ASSERT_TRUE(t.wrenchOnDevice.allFinite());
    ASSERT_TRUE(t.worldFromDevice.matrix().allFinite());
    ASSERT_TRUE(t.worldFromSimulation.matrix().allFinite());
  }
  EXPECT_EQ(r.ticks.back().qpState, static_cast<int>(ContactQpState::Stuck));
  // The user pulls: the device feels the god-object holding it back.
  EXPECT_GT(r.ticks.back().wrenchOnDevice.head<3>().norm(), 0.1);
}

TEST(HapticSession, VirtualTimeIsDeterministic) {
  const HapticScene scene = loadHapticScene(test::scenePath("thin-wire.json"));
  HapticSessionSettings s;
  s.method = HapticMethod::Constraint;
  s.seconds = 0.1;
  const HapticSessionResult a = runHapticSession(scene, s);
  const HapticSessionResult b = runHapticSession(scene, s);
  ASSERT_EQ(a.ticks.size(), b.ticks.size());
  for (std::size_t i = 0; i < a.ticks.size(); ++i) {
    ASSERT_TRUE(a.ticks[i].worldFromSimulation.isApprox(b.ticks[i].worldFromSimulation, 0.0));
    ASSERT_EQ(a.ticks[i].wrenchOnDevice, b.ticks[i].wrenchOnDevice);
  }
}

TEST(HapticSession, RealTimeTwoLoopsRun) {
  const HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  for (HapticMethod method : {HapticMethod::Constraint, HapticMethod::Penalty}) {
    HapticSessionSettings s;
    s.method = method;
    s.seconds = 0.15;
    s.realTime = true;
    const HapticSessionResult r = runHapticSession(scene, s);
    EXPECT_EQ(r.summary.hapticTicks, 150);
    EXPECT_EQ(r.ticks.size(), 150u);
    EXPECT_GT(r.summary.simCycles, 0);
    EXPECT_GT(r.summary.hapticRateHz, 0.0);  // measured, never asserted against 1 kHz
    if (method == HapticMethod::Constraint) {
      EXPECT_EQ(r.summary.maxPenetrationCells, 0.0);
    }
    EXPECT_TRUE(r.summary.finalPosition.allFinite());
  }
}

TEST(HapticSession, WritesTickCsvAndSummaryJson) {
  const HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  HapticSessionSettings s;
  s.seconds = 0.01;
  const HapticSessionResult r = runHapticSession(scene, s);
  const std::string path = ::testing::TempDir() + "/ticks.csv";
  writeTickCsv(path, r.ticks);
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("tick,time,device_x", 0), 0u);
  int rows = 0;
  for (std::string line; std::getline(in, line);) ++rows;
  EXPECT_EQ(rows, 10);
  const std::string json = summaryJson(r.summary);
  for (const char* key :
       {"\"method\"", "\"inserted\"", "\"max_penetration_cells\"", "\"tunneled\"", "\"haptic_rate_hz\"",
        "\"haptic_overruns\"", "\"sim_cycle_p50_ms\"", "\"sim_cycle_p99_ms\"", "\"max_contacts\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
}

// plane-slide with an absurd penalty stiffness (any positive value is allowed): the explicit-in-contact part of the
// step flings the box off the plane within a few dozen ticks.
HapticScene explodingPenaltyScene() {
  HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  scene.penalty.contact.stiffness = 1e12;
  return scene;
}

HapticSessionResult runPenalty(const HapticScene& scene, bool realTime = false) {
  HapticSessionSettings s;
  s.method = HapticMethod::Penalty;
  s.realTime = realTime;
  s.seconds = realTime ? 0.2 : 0.0;
  return runHapticSession(scene, s);
}

TEST(HapticGuard, ExplodingPenaltyObjectStopsTheLoopWithZeroForce) {
  const HapticSessionResult r = runPenalty(explodingPenaltyScene());
  EXPECT_TRUE(r.summary.guardStopped);
  EXPECT_NE(r.summary.runaway.find("body 'simulated object'"), std::string::npos) << r.summary.runaway;
  EXPECT_EQ(r.summary.runaway.find('\n'), std::string::npos);
  // Stopped early (the scene lasts 1600 ticks), every tick recorded, the last one rendering nothing.
  EXPECT_LT(r.summary.hapticTicks, 200);
  ASSERT_EQ(r.ticks.size(), static_cast<std::size_t>(r.summary.hapticTicks));
  EXPECT_EQ(r.ticks.back().wrenchOnDevice, Vec6::Zero());
  EXPECT_NE(summaryJson(r.summary).find("\"guard_stopped\": true"), std::string::npos);
}

TEST(HapticGuard, WithoutTheGuardTheSameSessionExplodes) {
  // The control: the violation above is real. With the guard off the session runs to its end, far off the plane.
  HapticScene scene = explodingPenaltyScene();
  scene.guard.action = GuardAction::Off;
  const HapticSessionResult r = runPenalty(scene);
  EXPECT_FALSE(r.summary.guardStopped);
  EXPECT_EQ(r.summary.runaway, "");
  EXPECT_EQ(r.summary.hapticTicks, 1600);
  EXPECT_FALSE(r.summary.finalPosition.allFinite() && r.summary.finalPosition.norm() < 1.0)
      << r.summary.finalPosition.transpose();
}

TEST(HapticGuard, ReportActionKeepsTheSessionRunning) {
  HapticScene scene = explodingPenaltyScene();
  scene.guard.action = GuardAction::Report;
  const HapticSessionResult r = runPenalty(scene);
  EXPECT_FALSE(r.summary.guardStopped);
  EXPECT_NE(r.summary.runaway.find("simulated object"), std::string::npos);
  EXPECT_EQ(r.summary.hapticTicks, 1600);
}

TEST(HapticGuard, RealTimeLoopStopsToo) {
  const HapticSessionResult r = runPenalty(explodingPenaltyScene(), /*realTime=*/true);
  EXPECT_TRUE(r.summary.guardStopped);
  EXPECT_LT(r.summary.hapticTicks, 200);  // the 0.2 s session ends at the violation
  ASSERT_FALSE(r.ticks.empty());
  EXPECT_EQ(r.ticks.back().wrenchOnDevice, Vec6::Zero());
}

TEST(HapticGuard, ConstraintMethodGodObjectThrownAcrossTheWorldStops) {
  // A forced state: the scripted hand is 50 m away from the start and the god-object's step limit is lifted, so the
  // god-object follows the device at tens of m/s while the script itself never moves (no kinematic budget).
  HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  Rigid far = Rigid::Identity();
  far.translation() = Vec3(50.0, 0.0101, 0.0);
  scene.script = UserScript({PoseKeyframe{0.0, far}, PoseKeyframe{0.5, far}});
  scene.god.maxStepTranslation = 1e9;
  scene.device.maxForce = 1e9;
  HapticSessionSettings s;
  s.method = HapticMethod::Constraint;
  s.seconds = 0.5;
  const HapticSessionResult r = runHapticSession(scene, s);
  EXPECT_TRUE(r.summary.guardStopped) << r.summary.finalPosition.transpose();
  EXPECT_NE(r.summary.runaway.find("simulated object"), std::string::npos);
  EXPECT_LT(r.summary.hapticTicks, 500);
  EXPECT_EQ(r.ticks.back().wrenchOnDevice, Vec6::Zero());
}

TEST(HapticScene, GuardKeyIsReadAndChecked) {
  const std::string path = ::testing::TempDir() + "/guard-scene.json";
  const auto write = [&](const std::string& guard) {
    std::ofstream f(path);
    f << "{\"obstacle\": {\"plane\": {\"normal\": [0,1,0]}}, \"shell\": {\"shape\": \"box\", \"halfExtents\": "
         "[0.01,0.01,0.01], \"points\": 50}, \"start\": {\"position\": [0,0.02,0]}, \"script\": [{\"t\": 0, "
         "\"position\": [0,0.02,0]}], \"guard\": "
      << guard << "}";
  };
  write("{\"action\": \"report\", \"max_speed\": 5, \"energy_factor\": 10, \"extent_factor\": 20}");
  const HapticScene scene = loadHapticScene(path);
  EXPECT_EQ(scene.guard.action, GuardAction::Report);
  EXPECT_EQ(scene.guard.maxSpeed, 5.0);
  EXPECT_EQ(scene.guard.energyFactor, 10.0);
  EXPECT_EQ(scene.guard.extentFactor, 20.0);
  for (const char* bad : {"{\"action\": \"explode\"}", "{\"max_speed\": 0.5}", "{\"speed\": 5}", "3"}) {
    write(bad);
    EXPECT_THROW(loadHapticScene(path), Error) << bad;
  }
}

TEST(HapticScene, BadFilesGiveOneLineErrors) {
  const std::string path = ::testing::TempDir() + "/bad-scene.json";
  const auto expectBad = [&](const std::string& text) {
    {
      std::ofstream f(path);
      f << text;
    }
    try {
      loadHapticScene(path);
      ADD_FAILURE() << "no error for " << text;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  };
  expectBad("{");
  expectBad("[]");
  expectBad("{\"obstacle\": {\"plane\": {\"normal\": [0,1,0]}}}");  // no shell
  expectBad("{\"obstacle\": {\"spacing\": -1, \"solids\": []}, \"shell\": {}}");
  expectBad("{\"obstacle\": {\"plane\": {\"normal\": [0,1,0]}}, \"shell\": {\"shape\": \"cone\"}}");
  expectBad(
      "{\"obstacle\": {\"plane\": {\"normal\": [0,1,0]}}, \"shell\": {\"shape\": \"box\", \"halfExtents\": "
      "[0.01,0.01,0.01], \"points\": 50}, \"start\": {\"position\": [0,0,0]}, \"script\": []}");
  expectBad(
      "{\"obstacle\": {\"plane\": {\"normal\": [0,1,0]}}, \"shell\": {\"shape\": \"box\", \"halfExtents\": "
      "[0.01,0.01,0.01], \"points\": 50}, \"start\": {\"position\": [0,0,0]}, \"script\": [{\"t\": 0, "
      "\"position\": [0,0,\"x\"]}]}");
  EXPECT_THROW(loadHapticScene(path + ".missing"), Error);
  EXPECT_THROW(parseHapticMethod("springs"), Error);
}

}  // namespace
}  // namespace sdfccd::haptics
