/// @file
/// @brief The per-axis gradient bounds (axis_lipschitz_bounds.h) and the coherent query's axis certificates
/// (src/ccd/rigid_ccd_axis_certificate.h): the bounds hold between random point pairs of noisy grids, whose
/// interpolant's gradient jumps across every cell face; a plate sliding along a wall with a sharp ridge (the
/// gradient along the slide jumps from 0 to steep there) gets the fresh query's contacts bit for bit at every step,
/// and the axis certificates skip work the isotropic ones cannot (fewer segment queries, counted, not timed).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "core/ccd/rigid_ccd_test_util.h"
#include "core/segment_reference.h"
#include "sdfccd/ccd/axis_lipschitz_bounds.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/ccd/rigid_ccd_coherence.h"
#include "sdfccd/field/grid_field.h"

namespace sdfccd {
namespace axis_certificate_test {

/// A wall at x = 0.5 (free space at x < 0.5) with a ridge jutting 0.15 out of it for y in [0.8, 1.0], plus uniform
/// noise of `noise` per node (0: none). Spacing 0.1.
std::shared_ptr<const SdfGrid> ridgedWall(double noise, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-noise, noise);
  return test::sampleGrid(Vec3i(25, 41, 25), Vec3(-1.2, -2.0, -1.2), 0.1, [&](const Vec3& p) {
    const double ridge = p.y() >= 0.8 && p.y() <= 1.0 ? 0.15 : 0.0;
    return 0.5 - ridge - p.x() + (noise > 0.0 ? jitter(rng) : 0.0);
  });
}

/// A square plate of 15 x 15 points in the shell's yz plane (normals +x) and 100 random points behind it.
PointShell plate(std::mt19937& rng) {
  PointShell shell;
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j) {
      shell.positions.emplace_back(0.0, -0.3 + 0.6 * i / 14.0, -0.3 + 0.6 * j / 14.0);
      shell.normals.push_back(Vec3::UnitX());
    }
  const PointShell ball = test::randomShell(100, 0.25, rng);
  for (std::size_t n = 0; n < ball.size(); ++n) {
    shell.positions.push_back(ball.positions[n] - Vec3(0.3, 0.0, 0.0));
    shell.normals.push_back(ball.normals[n]);
  }
  return shell;
}

TEST(AxisLipschitzBounds, HoldBetweenRandomPointPairsOfNoisyGrids) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  int pairs = 0;
  for (int grid = 0; grid < 4; ++grid) {
    const auto sdf = grid < 2 ? test::bumpyGrid(40 + grid, 0.08) : ridgedWall(grid == 2 ? 0.0 : 0.03, 9);
    const GridField field(sdf);
    for (const int blockCells : {1, 2, 3}) {
      const AxisLipschitzBounds bounds(*sdf, blockCells);
      const Box3 box = sdf->box();
      for (int n = 0; n < 4000; ++n) {
        const Vec3 p = box.min() + (box.max() - box.min()).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
        // Along one axis (crossing the cell faces squarely), or any direction; up to the full reach.
        Vec3 d = n % 3 == 0 ? Vec3::Unit(n % 9 / 3) : Vec3(g(rng), g(rng), g(rng)).normalized();
        d *= bounds.reach() * u(rng);
        const Vec3 q = p + d;
        if (!box.contains(q)) continue;
        const AxisLipschitzBounds::Block& b = bounds.block(bounds.blockOf(p));
        const double change = std::abs(field.distance(q) - field.distance(p));
        const double bound = b.x * std::abs(d.x()) + b.y * std::abs(d.y()) + b.z * std::abs(d.z());
        ASSERT_LE(change, bound * (1.0 + 1e-9) + 1e-12) << "grid " << grid << " block " << blockCells << " pair " << n;
        ASSERT_LE(change, b.norm * d.norm() * (1.0 + 1e-9) + 1e-12);
        ++pairs;
      }
    }
  }
  EXPECT_GT(pairs, 20000);
  // The bounds are not trivially loose: along a plain wall, nothing along it; across it, the wall's slope.
  const auto wall = ridgedWall(0.0, 1);
  const AxisLipschitzBounds bounds(*wall, 2);
  const AxisLipschitzBounds::Block& b = bounds.block(bounds.blockOf(Vec3(0.45, -1.0, 0.0)));
  EXPECT_EQ(b.y, 0.0f);
  EXPECT_EQ(b.z, 0.0f);
  EXPECT_NEAR(b.x, 1.0, 1e-6);
  EXPECT_GT(bounds.block(bounds.blockOf(Vec3(0.45, 0.75, 0.0))).y, 1.0f);  // the ridge's step
  EXPECT_EQ(bounds.blockOf(Vec3(5.0, 0.0, 0.0)), -1);
}

/// Slides the plate along the wall (y from -1.6 to 1.6, through the ridge) at `clearance` with a jitter across it
/// and a small wobble; every step's contacts are the fresh query's, with the axis certificates on and off. Returns
/// the segment queries of the two histories.
std::pair<std::int64_t, std::int64_t> slideAlongTheWall(const GridField& field, double clearance, CcdMode mode,
                                                        std::uint32_t seed, int* outContacts) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  const PointTree tree(plate(rng));
  RigidCcdSettings s;
  s.mode = mode;
  RigidCcdCoherence axis;
  axis.axisCertificates = true;
  RigidCcdCoherence plain;
  std::int64_t queries[2] = {0, 0};
  Rigid pose = Rigid::Identity();
  pose.translation() = Vec3(0.5 - clearance, -1.6, 0.0);
  for (int step = 0; step < 400; ++step) {
    Rigid next = pose;
    next.translation() = Vec3(0.5 - clearance + 0.002 * g(rng), -1.6 + 0.008 * (step + 1), 0.01 * g(rng));
    next.linear() = Eigen::AngleAxisd(0.003 * g(rng), Vec3(g(rng), g(rng), g(rng)).normalized()).toRotationMatrix();
    RigidCcdResult fresh;
    rigidCcd(tree, field, pose, next, s, fresh);
    *outContacts += static_cast<int>(fresh.contacts.size());
    RigidCcdCoherence* histories[2] = {&axis, &plain};
    for (int h = 0; h < 2; ++h) {
      RigidCcdResult coherent;
      rigidCcd(tree, field, pose, next, s, *histories[h], coherent);
      test::expectSameContacts(fresh, coherent, (h == 0 ? "axis step " : "plain step ") + std::to_string(step));
      if (::testing::Test::HasFatalFailure()) return {0, 0};
      queries[h] += coherent.stats.segmentQueries;
    }
    pose = next;
  }
  return {queries[0], queries[1]};
}

TEST(RigidCcdAxisCertificates, PlateSlidingAlongARidgedWallEqualsFresh) {
  int contacts = 0;
  for (const double noise : {0.0, 0.02}) {
    const GridField field(ridgedWall(noise, 21));
    for (const double clearance : {0.02, 0.06}) {
      for (const CcdMode mode : {CcdMode::AllIntervals, CcdMode::FirstHit}) {
        const auto [axis, plain] = slideAlongTheWall(field, clearance, mode, 5, &contacts);
        ASSERT_FALSE(HasFatalFailure());
        // Without noise the wall is flat along y and z: the axis certificates skip the slide's re-tests (close
        // to the wall, where the isotropic ones last a step or two, less than half the segment queries remain).
        if (noise == 0.0) {
          EXPECT_LT(clearance < 0.05 ? axis * 2 : axis, plain) << "clearance " << clearance;
        }
        EXPECT_LE(axis, plain);
      }
    }
  }
  EXPECT_GT(contacts, 1000);  // the ridge stops in the plate's way
}

TEST(RigidCcdAxisCertificates, RandomGridsUnderRandomPerturbationsEqualFresh) {
  std::mt19937 rng(29);
  std::normal_distribution<double> noise(0.0, 1.0);
  int contacts = 0;
  std::int64_t certified = 0;
  for (int field = 0; field < 6; ++field) {
    const test::RandomGridCase c = test::randomGridCase(300 + field, field, rng);
    const RigidCcdSettings s = test::variedGridSettings(field);
    RigidCcdCoherence history;
    history.axisCertificates = true;
    Rigid pose = test::randomPose(test::expanded(c.grid.grid().box(), 1.2), rng);
    for (int step = 0; step < 120; ++step) {
      // A random walk, mostly along one axis (what the axis certificates favour), a large step now and then.
      const double size = step % 17 == 0 ? 0.3 : 0.02;
      Rigid next = pose;
      next.translation() += size * Vec3(0.1 * noise(rng), noise(rng), 0.1 * noise(rng));
      next.linear() = pose.linear() * Eigen::AngleAxisd(0.2 * size * noise(rng), Vec3::UnitZ()).toRotationMatrix();
      if (!c.grid.grid().box().contains(next.translation())) next.translation() = c.grid.grid().box().center();
      RigidCcdResult fresh;
      rigidCcd(c.tree, c.grid, pose, next, s, fresh);
      RigidCcdResult coherent;
      rigidCcd(c.tree, c.grid, pose, next, s, history, coherent);
      test::expectSameContacts(fresh, coherent, "field " + std::to_string(field) + " step " + std::to_string(step));
      ASSERT_FALSE(HasFatalFailure());
      contacts += static_cast<int>(fresh.contacts.size());
      certified += coherent.stats.certified;
      pose = next;
    }
  }
  EXPECT_GT(contacts, 1000);
  EXPECT_GT(certified, 0);
}

}  // namespace axis_certificate_test
}  // namespace sdfccd
