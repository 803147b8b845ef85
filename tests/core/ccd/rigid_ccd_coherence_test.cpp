/// @file
/// @brief The coherent every-contact query (rigid_ccd_coherence.h) against the fresh one, step after step: the
/// bunny shell over the bunny field, random grids with random perturbations, jumps far away and back, the first
/// call without history, zero-length motion and grazing contact with the plane. Every step's contacts must be
/// the fresh query's bit for bit; each test also checks that the history did skip work (so it can fail both
/// ways: a wrong culling changes the contacts, a dead history shows no certified nodes).
#include "sdfccd/ccd/rigid_ccd_coherence.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>
#include <string>

#include "core/ccd/rigid_ccd_test_util.h"
#include "core/sdf_test_meshes.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/mesh/sdf_builder.h"

namespace sdfccd {
namespace {

/// Runs one step both ways and compares; returns the coherent query's stats.
template <class Field>
RigidCcdStats coherentStep(const PointTree& tree, const Field& field, const Rigid& a, const Rigid& b,
                           const RigidCcdSettings& s, RigidCcdCoherence& history, const std::string& what,
                           int* contacts = nullptr) {
  RigidCcdResult fresh;
  rigidCcd(tree, field, a, b, s, fresh);
  RigidCcdResult coherent;
  rigidCcd(tree, field, a, b, s, history, coherent);
  test::expectSameContacts(fresh, coherent, what);
  if (contacts) *contacts += static_cast<int>(fresh.contacts.size());
  return coherent.stats;
}

/// A pose on a smooth path: a circle of radius `r` about the origin in the xz plane, tumbling as it goes.
Rigid pathPose(double t, double r) {
  Rigid pose = Rigid::Identity();
  pose.linear() = (Eigen::AngleAxisd(0.7 * t, Vec3::UnitY()) * Eigen::AngleAxisd(0.3 * t, Vec3::UnitX())).matrix();
  pose.translation() = Vec3(r * std::cos(t), 0.15 * r * std::sin(2.0 * t), r * std::sin(t));
  return pose;
}

TEST(RigidCcdCoherence, BunnyOverTheBunnyFieldEqualsFreshAtEveryStep) {
  TriangleMesh mesh = test::readOff(std::string(SDFCCD_ASSETS_DIR) + "/meshes/bunny.off");
  repairMesh(mesh);
  SdfBuildSettings build;
  build.resolution = 40;
  build.threads = 2;
  const GridField field(buildSdf(mesh, build).grid);
  ShellSamplingSettings sampling;
  sampling.points = 777;
  sampling.iterations = 5;
  PointShell shell = sampleShell(mesh, sampling);
  const Vec3 centre = mesh.bounds().center();
  for (auto& p : shell.positions) p -= centre;
  const PointTree tree(shell);
  // The shell circles through the field at a radius where it overlaps it half of the time.
  const double r = 0.6 * field.grid().box().sizes().maxCoeff();
  RigidCcdCoherence history;
  int contacts = 0;
  std::int64_t certified = 0;
  for (int step = 0; step < 400; ++step) {
    const double t0 = 0.02 * step;
    RigidCcdSettings s;
    s.sigma = step < 200 ? 0.0 : 0.01;  // a new sigma starts afresh
    s.mode = step % 50 < 40 ? CcdMode::AllIntervals : CcdMode::FirstHit;
    certified += coherentStep(tree, field, pathPose(t0, r), pathPose(t0 + 0.02, r), s, history,
                              "bunny step " + std::to_string(step), &contacts)
                     .certified;
  }
  EXPECT_GT(contacts, 1000);
  EXPECT_GT(certified, 0);
}

TEST(RigidCcdCoherence, RandomGridsUnderRandomPerturbationsEqualFresh) {
  std::mt19937 rng(17);
  std::normal_distribution<double> noise(0.0, 1.0);
  int contacts = 0;
  std::int64_t certified = 0;
  for (int field = 0; field < 6; ++field) {
    const test::RandomGridCase c = test::randomGridCase(100 + field, field, rng);
    const RigidCcdSettings s = test::variedGridSettings(field);
    RigidCcdCoherence history;
    Rigid pose = test::randomPose(test::expanded(c.grid.grid().box(), 1.2), rng);
    for (int step = 0; step < 120; ++step) {
      // A random walk: small steps, a large one now and then.
      const double size = step % 17 == 0 ? 0.3 : 0.02;
      Rigid next = pose;
      next.translation() += size * Vec3(noise(rng), noise(rng), noise(rng));
      next.linear() = pose.linear() * Eigen::AngleAxisd(size * noise(rng), Vec3::UnitZ()).toRotationMatrix() *
                      Eigen::AngleAxisd(size * noise(rng), Vec3::UnitX()).toRotationMatrix();
      if (!c.grid.grid().box().contains(next.translation())) next.translation() = c.grid.grid().box().center();
      certified += coherentStep(c.tree, c.grid, pose, next, s, history,
                                "field " + std::to_string(field) + " step " + std::to_string(step), &contacts)
                       .certified;
      pose = next;
    }
  }
  EXPECT_GT(contacts, 1000);
  EXPECT_GT(certified, 0);
}

TEST(RigidCcdCoherence, JumpsFarAwayAndBackEqualFresh) {
  std::mt19937 rng(5);
  const test::RandomGridCase c = test::randomGridCase(7, 0, rng);
  const RigidCcdSettings s;
  RigidCcdCoherence history;
  // A pose where the shell touches the field (drawn until one does).
  Rigid near = test::randomPose(c.grid.grid().box(), rng);
  for (int tries = 0; tries < 100 && test::run(c.tree, c.grid, near, near, s).contacts.empty(); ++tries) {
    near = test::randomPose(c.grid.grid().box(), rng);
  }
  Rigid far = near;
  far.translation() += Vec3(50.0, 0.0, 0.0);
  int contacts = 0;
  // The first call has no history; then near, far, near again, and steps that cross from far to near.
  const Rigid sequence[][2] = {{near, near}, {near, far}, {far, far},   {far, near}, {near, near},
                               {far, far},   {far, far},  {near, near}, {near, far}, {far, near}};
  for (int k = 0; k < 10; ++k) {
    coherentStep(c.tree, c.grid, sequence[k][0], sequence[k][1], s, history, "jump " + std::to_string(k), &contacts);
  }
  EXPECT_GT(contacts, 0);
  // Far from the field the whole shell is ruled out by its root: the front collapses to it.
  coherentStep(c.tree, c.grid, far, far, s, history, "far again");
  EXPECT_EQ(history.frontSize(), 1u);
  const RigidCcdStats stats = coherentStep(c.tree, c.grid, far, far, s, history, "far, once more");
  EXPECT_EQ(stats.certified, 1);
  EXPECT_EQ(stats.segmentQueries, 0);
}

TEST(RigidCcdCoherence, ZeroLengthMotionAndIgnoredPointsEqualFresh) {
  std::mt19937 rng(3);
  const test::RandomGridCase c = test::randomGridCase(11, 2, rng);
  RigidCcdSettings s;
  RigidCcdCoherence history;
  const Rigid pose = test::randomPose(c.grid.grid().box(), rng);
  std::vector<std::uint8_t> ignored(static_cast<std::size_t>(c.tree.pointCount()), 0);
  int contacts = 0;
  std::int64_t certified = 0;
  for (int step = 0; step < 20; ++step) {
    // The discrete model's query: start = end; every third step ignores a changing set of points.
    for (std::size_t p = 0; p < ignored.size(); ++p) ignored[p] = (step % 3 == 0 && (p + step) % 4 == 0) ? 1 : 0;
    s.ignoredPoints = &ignored;
    certified +=
        coherentStep(c.tree, c.grid, pose, pose, s, history, "still " + std::to_string(step), &contacts).certified;
  }
  EXPECT_GT(contacts, 0);
  EXPECT_GT(certified, 0);
}

TEST(RigidCcdCoherence, GrazingThePlaneEqualsFresh) {
  // A flat grid of points exactly at sigma above the ground slides along it, then lifts by tiny amounts.
  PointShell shell;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      shell.positions.emplace_back(0.01 * i, 0.0, 0.01 * j);
      shell.normals.emplace_back(0.0, -1.0, 0.0);
      shell.areas.push_back(1e-4);
    }
  }
  const PointTree tree(shell);
  const PlaneField ground = PlaneField::ground();
  RigidCcdSettings s;
  s.sigma = 0.001;
  RigidCcdCoherence history;
  int contacts = 0;
  const double lifts[] = {0.0, 0.0, 1e-16, 1e-12, 1e-9, 0.0, -1e-12, 1e-6, 0.0, 1e-3, 0.0};
  for (int step = 0; step < 11; ++step) {
    Rigid a = Rigid::Identity();
    a.translation() = Vec3(0.001 * step, s.sigma + lifts[step], 0.0);
    Rigid b = a;
    b.translation().x() += 0.001;
    coherentStep(tree, ground, a, b, s, history, "grazing " + std::to_string(step), &contacts);
  }
  EXPECT_GT(contacts, 0);
}

TEST(RigidCcdCoherence, AnotherTreeOrFieldStartsAfresh) {
  std::mt19937 rng(9);
  const test::RandomGridCase one = test::randomGridCase(21, 0, rng);
  const test::RandomGridCase two = test::randomGridCase(22, 1, rng);
  const RigidCcdSettings s;
  RigidCcdCoherence history;
  int contacts = 0;
  for (int step = 0; step < 8; ++step) {
    const test::RandomGridCase& c = step % 2 == 0 ? one : two;
    const Rigid a = test::randomPose(c.grid.grid().box(), rng);
    coherentStep(c.tree, c.grid, a, test::shortStepFrom(a, a), s, history, "swap " + std::to_string(step), &contacts);
    coherentStep(one.tree, two.grid, a, a, s, history, "mixed " + std::to_string(step), &contacts);
  }
  EXPECT_GT(contacts, 0);
}

/// The grid's values lowered by `drop` (everything `drop` deeper; the same gradients, so the same bound).
std::shared_ptr<const SdfGrid> loweredGrid(const SdfGrid& grid, float drop) {
  std::vector<float> values = grid.values();
  for (float& v : values) v -= drop;
  return std::make_shared<const SdfGrid>(grid.nodeCounts(), grid.origin(), grid.spacing(), std::move(values));
}

TEST(RigidCcdCoherence, AnotherFieldOrTreeAtTheSameAddressStartsAfresh) {
  // A per-step local field (or a rebuilt tree) lands at the freed one's address: the history must not take
  // the old object's certificates for the new one's. The lowered field touches where the first one certified
  // clearance, with the same node count, sigma and gradient bound, so only the instance ids (instance_id.h) tell
  // the two apart.
  std::mt19937 rng(31);
  const test::RandomGridCase c = test::randomGridCase(23, 0, rng);
  const std::shared_ptr<const SdfGrid> high = c.grid.gridPtr();
  const std::shared_ptr<const SdfGrid> low = loweredGrid(*high, 0.3f);
  const RigidCcdSettings s;
  RigidCcdCoherence history;
  std::optional<GridField> field;
  std::optional<PointTree> tree;
  int contacts = 0;
  for (int step = 0; step < 8; ++step) {
    field.reset();
    field.emplace(step % 2 == 0 ? high : low);
    const Rigid a = test::randomPose(high->box(), rng);
    for (int still = 0; still < 3; ++still) {  // the same pose again: every certificate holds for the same field
      coherentStep(c.tree, *field, a, a, s, history, "field " + std::to_string(step), &contacts);
    }
  }
  PointTreeSettings binary;  // the case's tree settings: the same node count for every tree of 700 points
  binary.branching = 2;
  for (int step = 0; step < 8; ++step) {
    tree.reset();
    tree.emplace(step % 2 == 0 ? c.tree.shell() : test::randomShell(700, 0.6, rng), binary);
    ASSERT_EQ(tree->nodeCount(), c.tree.nodeCount());
    const Rigid a = test::randomPose(high->box(), rng);
    for (int still = 0; still < 3; ++still) {
      coherentStep(*tree, *field, a, a, s, history, "tree " + std::to_string(step), &contacts);
    }
  }
  EXPECT_GT(contacts, 0);
}

/// A query that starts where the last one ended takes the kept poses' distances to its start from that query
/// (RigidCcdCoherence::lastEnd). Here most steps chain (start = last end) and every few steps one starts
/// elsewhere, inside the field, and ends back at the last end: the distances from that start must be measured,
/// else the front's certificates see almost no motion and miss the contacts along the way in. Length and axis
/// certificates alike.
TEST(RigidCcdCoherence, StepsThatDoNotStartAtTheLastEndEqualFresh) {
  std::mt19937 rng(41);
  std::normal_distribution<double> noise(0.0, 1.0);
  int contacts = 0;
  int detourContacts = 0;
  std::int64_t certified = 0;
  for (int field = 0; field < 6; ++field) {
    const test::RandomGridCase c = test::randomGridCase(500 + field, field, rng);
    const RigidCcdSettings s = test::variedGridSettings(field);
    RigidCcdCoherence history;
    history.axisCertificates = field % 2 == 1;
    const Box3 box = c.grid.grid().box();
    Rigid pose = test::randomPose(test::expanded(box, 1.2), rng);
    for (int step = 0; step < 120; ++step) {
      const std::string what = "field " + std::to_string(field) + " step " + std::to_string(step);
      if (step % 5 == 4) {
        // The detour: from a random pose in the field's box back to the last end (a zero-length chain step
        // follows, so the next chained step starts at an end pose again).
        const Rigid detour = test::randomPose(box, rng);
        int before = contacts;
        certified += coherentStep(c.tree, c.grid, detour, pose, s, history, what + " detour", &contacts).certified;
        detourContacts += contacts - before;
        continue;
      }
      Rigid next = pose;
      next.translation() += 0.02 * Vec3(noise(rng), noise(rng), noise(rng));
      next.linear() = pose.linear() * Eigen::AngleAxisd(0.02 * noise(rng), Vec3::UnitZ()).toRotationMatrix();
      if (!box.contains(next.translation())) next.translation() = box.center();
      certified += coherentStep(c.tree, c.grid, pose, next, s, history, what, &contacts).certified;
      pose = next;
    }
  }
  EXPECT_GT(detourContacts, 100);  // the detours do cross the field
  EXPECT_GT(contacts, 1000);
  EXPECT_GT(certified, 0);
}

}  // namespace
}  // namespace sdfccd
