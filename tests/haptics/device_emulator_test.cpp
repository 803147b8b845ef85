/// @file
/// @brief DeviceEmulator and UserScript: the scripted hand pulls the device to its target; force limits;
/// keyframe interpolation; CSV trajectories and their errors; virtual-time determinism; the real-time loop.
#include "sdfccd/haptics/device_emulator.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <thread>

#include "sdfccd/error.h"
#include "sdfccd/haptics/latest_value.h"

namespace sdfccd::haptics {
namespace {

Rigid pose(const Vec3& p, const Quat& q = Quat::Identity()) {
  Rigid r = Rigid::Identity();
  r.linear() = q.toRotationMatrix();
  r.translation() = p;
  return r;
}

TEST(UserScript, InterpolatesPositionsLinearlyAndOrientationsBySlerp) {
  const Quat q1(Eigen::AngleAxisd(1.0, Vec3::UnitZ()));
  const UserScript script({{0.0, pose(Vec3(0, 0, 0))}, {2.0, pose(Vec3(2, -4, 6), q1)}});
  const Rigid mid = script.targetAt(0.5);
  EXPECT_TRUE(mid.translation().isApprox(Vec3(0.5, -1.0, 1.5)));
  EXPECT_NEAR(Eigen::AngleAxisd(mid.linear()).angle(), 0.25, 1e-12);
  EXPECT_TRUE(script.targetAt(-1.0).isApprox(pose(Vec3::Zero())));
  EXPECT_TRUE(script.targetAt(5.0).isApprox(pose(Vec3(2, -4, 6), q1)));
  EXPECT_THROW(UserScript(std::vector<PoseKeyframe>{}), Error);
  EXPECT_THROW(UserScript({{1.0, pose(Vec3::Zero())}, {1.0, pose(Vec3::Ones())}}), Error);
}

TEST(UserScript, LoadsRecordedCsvAndRejectsBadFiles) {
  const std::string path = ::testing::TempDir() + "/traj.csv";
  {
    std::ofstream f(path);
    f << "t,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n1,1,2,3,2,0,0,0\n";
  }
  const UserScript s = UserScript::loadCsv(path);
  ASSERT_EQ(s.keys().size(), 2u);
  EXPECT_TRUE(s.targetAt(0.5).translation().isApprox(Vec3(0.5, 1.0, 1.5)));
  EXPECT_TRUE(s.targetAt(1.0).linear().isApprox(Mat3::Identity()));  // quaternion normalized
  const auto expectBad = [&](const std::string& text) {
    {
      std::ofstream f(path);
      f << text;
    }
    EXPECT_THROW(UserScript::loadCsv(path), Error) << text;
  };
  expectBad("");
  expectBad("t,x,y\n0,0,0\n");
  expectBad("t,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0\n");
  expectBad("t,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,abc\n");
  expectBad("t,x,y,z,qw,qx,qy,qz\n0,0,0,nan,1,0,0,0\n");
  expectBad("t,x,y,z,qw,qx,qy,qz\n0,0,0,0,0,0,0,0\n");
  expectBad("t,x,y,z,qw,qx,qy,qz\n1,0,0,0,1,0,0,0\n0,0,0,0,1,0,0,0\n");
  expectBad("t,x,y,z,qw,qx,qy,qz\n");
  std::remove(path.c_str());
  EXPECT_THROW(UserScript::loadCsv(path), Error);
}

TEST(DeviceEmulator, ScriptedUserPullsTheDeviceToItsTarget) {
  const Quat q(Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized()));
  const UserScript script({{0.0, pose(Vec3::Zero())}, {0.5, pose(Vec3(0.05, -0.02, 0.01), q)}});
  DeviceEmulator device(DeviceSettings{}, script, pose(Vec3::Zero()));
  const LoopTimingStats stats = device.runVirtual(4000, nullptr);
  EXPECT_EQ(stats.ticks, 4000);
  EXPECT_TRUE(stats.virtualTime);
  EXPECT_NEAR(device.state().time, 4.0, 1e-9);
  const Vec6 err = poseDifference(device.state().body.worldFromBody, pose(Vec3(0.05, -0.02, 0.01), q));
  EXPECT_LT(err.head<3>().norm(), 1e-4);
  EXPECT_LT(err.tail<3>().norm(), 1e-3);
}

TEST(DeviceEmulator, RenderedWrenchIsClampedToTheDeviceLimits) {
  DeviceSettings settings;
  settings.maxForce = 5.0;
  settings.maxTorque = 0.5;
  DeviceEmulator device(settings, UserScript({{0.0, pose(Vec3::Zero())}}), pose(Vec3::Zero()));
  Vec6 w;
  w << 100, 0, 0, 0, -50, 0;
  device.step(w);
  EXPECT_NEAR(device.state().renderedWrench.head<3>().norm(), 5.0, 1e-12);
  EXPECT_NEAR(device.state().renderedWrench.tail<3>().norm(), 0.5, 1e-12);
  // dt = 1 ms: v = F dt / m.
  EXPECT_NEAR(device.state().body.linearVelocity.x(), 5.0 * 1e-3 / settings.mass, 1e-12);
  w.setConstant(std::nan(""));
  device.step(w);
  EXPECT_TRUE(device.state().body.worldFromBody.matrix().allFinite());
  EXPECT_EQ(device.state().renderedWrench, Vec6::Zero());
}

TEST(DeviceEmulator, VirtualTimeIsDeterministic) {
  const UserScript script({{0.0, pose(Vec3::Zero())}, {0.3, pose(Vec3(0.1, 0, 0))}});
  const auto run = [&] {
    DeviceEmulator device(DeviceSettings{}, script, pose(Vec3::Zero()));
    device.runVirtual(700, [](const DeviceState& s) {
      Vec6 w = Vec6::Zero();
      w[0] = -100.0 * std::max(0.0, s.body.worldFromBody.translation().x() - 0.05);  // a wall at x = 0.05
      return w;
    });
    return device.state().body.worldFromBody;
  };
  EXPECT_TRUE(run().isApprox(run(), 0.0));
}

TEST(DeviceEmulator, BadSettingsThrow) {
  DeviceSettings s;
  s.rateHz = 0.0;
  EXPECT_THROW(DeviceEmulator(s, UserScript({{0.0, pose(Vec3::Zero())}}), pose(Vec3::Zero())), Error);
  s = DeviceSettings{};
  s.mass = std::nan("");
  EXPECT_THROW(DeviceEmulator(s, UserScript({{0.0, pose(Vec3::Zero())}}), pose(Vec3::Zero())), Error);
}

TEST(DeviceEmulator, RealTimeLoopRunsItsTicksAndExchangesWithAnotherThread) {
  const UserScript script({{0.0, pose(Vec3::Zero())}, {0.1, pose(Vec3(0.02, 0, 0))}});
  DeviceEmulator device(DeviceSettings{}, script, pose(Vec3::Zero()));
  LatestValue<Rigid> devicePose;
  LatestValue<Vec6> wrench;
  std::atomic<bool> done{false};
  std::thread simulation([&] {
    Rigid p = Rigid::Identity();
    while (!done.load()) {
      if (devicePose.read(p) != 0) {
        Vec6 w = Vec6::Zero();
        w[0] = -10.0 * p.translation().x();
        wrench.publish(w);
      }
      std::this_thread::yield();
    }
  });
  device.start(
      [&](const DeviceState& s) {
        devicePose.publish(s.body.worldFromBody);
        Vec6 w = Vec6::Zero();
        wrench.read(w);
        return w;
      },
      150);
  device.wait();
  done = true;
  simulation.join();
  const LoopTimingStats& stats = device.stats();
  EXPECT_EQ(stats.ticks, 150);
  EXPECT_FALSE(stats.virtualTime);
  EXPECT_GT(stats.achievedRateHz, 0.0);  // the rate itself is measured, never asserted
  EXPECT_GE(stats.jitterP99Us, stats.jitterP50Us);
  EXPECT_GT(device.state().body.worldFromBody.translation().x(), 0.0);
  EXPECT_FALSE(device.running());
}

}  // namespace
}  // namespace sdfccd::haptics
