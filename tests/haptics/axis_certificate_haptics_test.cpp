/// @file
/// @brief The axis certificates (axis_lipschitz_bounds.h) in the haptic loop, against the fresh answers bit for bit:
/// the penalty renderer's coherent CCD and the god-object's clearance cache on the peg in the hole with 6,000 points
/// (the peg slides along the hole's wall: what the certificates are for), and the god-object pushing a plate along a
/// wall into a ridge, where the gradient along the slide jumps from 0 to steep across one cell face. Each test also
/// counts that the axis certificates saved segment queries (so it can fail both ways).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <utility>

#include "core/segment_reference.h"
#include "haptics/haptic_test_scenes.h"
#include "sdfccd/haptics/device_emulator.h"
#include "sdfccd/haptics/god_object.h"
#include "sdfccd/haptics/haptic_scene.h"
#include "sdfccd/haptics/penalty_renderer.h"

namespace sdfccd::haptics {
namespace axis_certificate_haptics_test {

HapticScene pegScene(int points) {
  HapticScene scene = loadHapticScene(test::scenePath("peg-in-hole.json"));
  resampleSceneShell(scene, points);
  return scene;
}

TEST(PenaltyRendererAxisCertificates, PegSlideIsBitIdenticalToTheFreshQuery) {
  const HapticScene scene = pegScene(6000);
  ASSERT_TRUE(scene.grid);
  const auto makeSettings = [&](bool coherent, bool axis) {
    PenaltyRendererSettings s = scene.penalty;
    s.contact.model = PenaltyModel::Continuous;
    s.timestep = 1.0 / scene.device.rateHz;
    s.coherentCcd = coherent;
    s.axisCertificates = axis;
    return s;
  };
  PenaltyRenderer fresh(ObstacleContacts(*scene.tree, *scene.grid, scene.worldFromSdf), scene.worldFromBodyStart,
                        makeSettings(false, false));
  PenaltyRenderer axis(ObstacleContacts(*scene.tree, *scene.grid, scene.worldFromSdf), scene.worldFromBodyStart,
                       makeSettings(true, true));
  PenaltyRenderer plain(ObstacleContacts(*scene.tree, *scene.grid, scene.worldFromSdf), scene.worldFromBodyStart,
                        makeSettings(true, false));
  DeviceEmulator deviceA(scene.device, scene.script, scene.worldFromBodyStart);
  DeviceEmulator deviceB(scene.device, scene.script, scene.worldFromBodyStart);
  DeviceEmulator deviceC(scene.device, scene.script, scene.worldFromBodyStart);
  const int ticks = static_cast<int>(scene.seconds * scene.device.rateHz);
  std::int64_t axisQueries = 0, plainQueries = 0;
  int contactTicks = 0, mismatches = 0;
  const auto same = [](const PenaltyStepResult& a, const PenaltyStepResult& b, const PenaltyRenderer& ra,
                       const PenaltyRenderer& rb) {
    return a.contactWrench == b.contactWrench && a.contactCount == b.contactCount &&
           ra.state().worldFromBody.matrix() == rb.state().worldFromBody.matrix() &&
           a.wrenchOnDevice == b.wrenchOnDevice;
  };
  for (int n = 0; n < ticks; ++n) {
    const PenaltyStepResult a = fresh.step(deviceA.state().body);
    const PenaltyStepResult b = axis.step(deviceB.state().body);
    const PenaltyStepResult c = plain.step(deviceC.state().body);
    mismatches += !same(a, b, fresh, axis) + !same(a, c, fresh, plain);
    contactTicks += a.contactCount > 0;
    axisQueries += b.segmentQueries;
    plainQueries += c.segmentQueries;
    deviceA.step(a.wrenchOnDevice);
    deviceB.step(b.wrenchOnDevice);
    deviceC.step(c.wrenchOnDevice);
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(contactTicks, 500);
  EXPECT_LT(axisQueries, plainQueries * 3 / 4);  // measured: about half
}

/// Drives god-objects with the cache off, on with axis certificates and on without them by `target(k)`; every cycle
/// of the cached ones must be the uncached one's bit for bit. Returns the segment queries with and without axis.
template <class Target>
std::pair<std::int64_t, std::int64_t> compareGodObjects(const PointTree& tree, const GridField& field,
                                                        const Rigid& worldFromSdf, const Rigid& start,
                                                        const GodObjectSettings& settings, int cycles, Target target,
                                                        int* outContactCycles) {
  GodObjectSettings off = settings;
  off.clearanceCache = false;
  GodObjectSettings axisOn = settings;
  axisOn.clearanceCache = true;
  axisOn.axisCertificates = true;
  GodObjectSettings axisOff = axisOn;
  axisOff.axisCertificates = false;
  GodObject reference(ObstacleContacts(tree, field, worldFromSdf), start, off);
  GodObject withAxis(ObstacleContacts(tree, field, worldFromSdf), start, axisOn);
  GodObject withoutAxis(ObstacleContacts(tree, field, worldFromSdf), start, axisOff);
  std::int64_t queries[2] = {0, 0};
  for (int k = 0; k < cycles; ++k) {
    const Rigid t = target(k);
    const GodObjectStepResult r = reference.step(t);
    GodObject* cached[2] = {&withAxis, &withoutAxis};
    for (int h = 0; h < 2; ++h) {
      const GodObjectStepResult c = cached[h]->step(t);
      const std::string what = std::string(h == 0 ? "axis" : "no axis") + " cycle " + std::to_string(k);
      EXPECT_EQ(c.fraction, r.fraction) << what;
      EXPECT_EQ(c.nextContactCount, r.nextContactCount) << what;
      EXPECT_TRUE(cached[h]->pose().matrix() == reference.pose().matrix()) << what;
      EXPECT_EQ(cached[h]->contacts().size(), reference.contacts().size()) << what;
      if (::testing::Test::HasFailure()) return {0, 0};
      for (std::size_t n = 0; n < reference.contacts().size(); ++n)
        EXPECT_EQ(cached[h]->contacts()[n].point, reference.contacts()[n].point) << what;
      queries[h] += c.segmentQueries;
    }
    *outContactCycles += r.nextContactCount > 0;
  }
  return {queries[0], queries[1]};
}

TEST(GodObjectAxisCertificates, PegSlideIsBitIdenticalWithoutTheCache) {
  const HapticScene scene = pegScene(6000);
  int contactCycles = 0;
  const auto [axis, plain] = compareGodObjects(
      *scene.tree, *scene.grid, scene.worldFromSdf, scene.worldFromBodyStart, scene.god,
      static_cast<int>(scene.seconds * 1000.0), [&](int k) { return scene.script.targetAt(1e-3 * k); }, &contactCycles);
  ASSERT_FALSE(HasFailure());
  EXPECT_GT(contactCycles, 500);
  EXPECT_LT(axis, plain);
}

TEST(GodObjectAxisCertificates, PlatePushedAlongAWallIntoARidgeIsBitIdenticalWithoutTheCache) {
  // A wall at x = 0.5 (free space x < 0.5), a ridge jutting 0.15 out of it for y in [0.8, 1.0]; spacing 0.1. With
  // noise on the second run, the gradient jumps at every cell face.
  for (const double noise : {0.0, 0.02}) {
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> jitter(-noise, noise);
    const GridField field(sdfccd::test::sampleGrid(Vec3i(25, 41, 25), Vec3(-1.2, -2.0, -1.2), 0.1, [&](const Vec3& p) {
      const double ridge = p.y() >= 0.8 && p.y() <= 1.0 ? 0.15 : 0.0;
      return 0.5 - ridge - p.x() + (noise > 0.0 ? jitter(rng) : 0.0);
    }));
    PointShell shell;  // a 20 x 20 plate in the yz plane facing the wall
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 20; ++j) {
        shell.positions.emplace_back(0.0, -0.3 + 0.6 * i / 19.0, -0.3 + 0.6 * j / 19.0);
        shell.normals.push_back(Vec3::UnitX());
      }
    const PointTree tree(shell);
    GodObjectSettings settings;
    settings.sigma = 0.002;
    settings.contactThreshold = 0.002;
    settings.maxStepTranslation = 0.2;
    Rigid start = Rigid::Identity();
    start.translation() = Vec3(0.42, -1.5, 0.0);
    // Pressed into the wall (the target 0.05 behind it) while dragged along y up to and over the ridge, turning a
    // little: the plate slides on the wall, then the ridge stops it.
    const auto target = [](int k) {
      Rigid t = Rigid::Identity();
      t.translation() = Vec3(0.55, -1.5 + 0.004 * k, 0.02 * std::sin(0.01 * k));
      t.linear() = Eigen::AngleAxisd(0.01 * std::sin(0.02 * k), Vec3::UnitZ()).toRotationMatrix();
      return t;
    };
    int contactCycles = 0;
    const auto [axis, plain] =
        compareGodObjects(tree, field, Rigid::Identity(), start, settings, 700, target, &contactCycles);
    ASSERT_FALSE(HasFailure()) << "noise " << noise;
    EXPECT_GT(contactCycles, 300) << "noise " << noise;
    EXPECT_LE(axis, plain) << "noise " << noise;
  }
}

}  // namespace axis_certificate_haptics_test
}  // namespace sdfccd::haptics
