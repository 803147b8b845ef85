/// @file
/// @brief Rigid CCD of point trees against fields: closed-form first hits against the plane and the sphere;
/// tree == linear (serial and threaded) on random shells vs random grid fields and on the bunny and dragon
/// vs their SDFs; no node is ever culled above a colliding point (brute force over every node).
#include "sdfccd/ccd/rigid_ccd.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/ccd/rigid_ccd_test_util.h"
#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/mesh/procedural_meshes.h"
#include "sdfccd/mesh/sdf_builder.h"

namespace sdfccd {
namespace {

using namespace test;  // rigid_ccd_test_util.h and the shell helpers

TEST(RigidCcd, ShellFallingOntoThePlaneHitsAtTheClosedFormFraction) {
  const PointTree tree(shellFromVertices(makeIcosphere(1.0, 3)));
  const PlaneField ground = PlaneField::ground();
  Rigid start = Rigid::Identity();
  start.linear() = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  start.translation() = Vec3(0.5, 3.0, -0.25);
  Rigid end = start;
  end.translation() = Vec3(0.5, -0.5, -0.25);  // translation only: every point moves by (0, -3.5, 0)
  double lowest = std::numeric_limits<double>::infinity();
  int expectedContacts = 0;
  for (const auto& x : tree.shell().positions) {
    const double y0 = (start * x).y();
    lowest = std::min(lowest, y0);
    if (y0 - 3.5 <= 0.0) ++expectedContacts;
  }
  RigidCcdSettings settings;
  const RigidCcdResult r = checkTreeEqualsLinear(tree, ground, start, end, settings, "plane");
  EXPECT_NEAR(r.firstFraction, lowest / 3.5, 1e-14);
  ASSERT_EQ(static_cast<int>(r.contacts.size()), expectedContacts);
  for (const auto& c : r.contacts) {
    const Vec3 x = tree.shell().positions[c.point];
    const double y0 = (start * x).y();
    EXPECT_EQ(c.state, SegmentState::Hit);
    EXPECT_NEAR(c.fraction, y0 / 3.5, 1e-14);
    EXPECT_NEAR(c.depthAtEnd, y0 - 3.5, 1e-14);
    ASSERT_EQ(c.intervals.size(), 1u);
    EXPECT_NEAR(c.intervals[0].begin, y0 / 3.5, 1e-14);
    EXPECT_EQ(c.intervals[0].end, 1.0);
    EXPECT_TRUE(c.fieldNormalInSdf.isApprox(Vec3::UnitY()));
    EXPECT_EQ(c.pointNormalInShell, tree.shell().normals[c.point]);
  }
  for (std::size_t n = 1; n < r.contacts.size(); ++n) EXPECT_LT(r.contacts[n - 1].point, r.contacts[n].point);
  // sigma lifts the level set: first contact earlier by sigma / 3.5.
  settings.sigma = 0.7;
  const RigidCcdResult lifted = checkTreeEqualsLinear(tree, ground, start, end, settings, "plane, sigma");
  EXPECT_NEAR(lifted.firstFraction, (lowest - 0.7) / 3.5, 1e-14);
  // The tree culls: far fewer queries than points when only the bottom touches.
  settings.sigma = 0.0;
  end.translation().y() = 0.9;  // only the lowest cap reaches the ground
  const RigidCcdResult tree1 = run(tree, ground, start, end, settings);
  EXPECT_GT(tree1.contacts.size(), 0u);
  EXPECT_LT(tree1.stats.segmentQueries, tree.pointCount() / 2);
}

TEST(RigidCcd, RotatingShellAgainstTheSphereMatchesPerPointClosedForm) {
  std::mt19937 rng(21);
  const PointTree tree(sampleBowl(600, 10));
  const SphereField sphere(Vec3(0.2, -0.1, 0.3), 0.8);
  const Box3 poses(Vec3::Constant(-2.5), Vec3::Constant(2.5));
  int contacts = 0;
  for (int config = 0; config < 150; ++config) {
    const Rigid a = test::randomPose(poses, rng);
    const Rigid b = test::randomPose(poses, rng);
    const RigidCcdSettings settings = variedSphereSettings(config);
    const RigidCcdResult r = checkTreeEqualsLinear(tree, sphere, a, b, settings, "sphere " + std::to_string(config));
    // Per point, independently: the quadratic |p(t) - c|^2 = (r + sigma)^2.
    std::size_t next = 0;
    for (int p = 0; p < tree.pointCount(); ++p) {
      const Vec3 p0 = a * tree.shell().positions[p];
      const Vec3 p1 = b * tree.shell().positions[p];
      const Vec3 d = p1 - p0;
      const Vec3 m = p0 - sphere.center();
      const double big = sphere.radius() + settings.sigma;
      const double qa = d.squaredNorm(), qb = d.dot(m), qc = m.squaredNorm() - big * big;
      const double disc = qb * qb - qa * qc;
      bool hit = qc <= 0.0;
      double first = 0.0;
      if (!hit && disc >= 0.0) {
        first = (-qb - std::sqrt(disc)) / qa;
        hit = first >= 0.0 && first <= 1.0;
      }
      if (!hit) continue;
      ASSERT_LT(next, r.contacts.size());
      const PointContact& c = r.contacts[next++];
      ASSERT_EQ(c.point, p);
      EXPECT_NEAR(c.fraction, first, 1e-9);
      EXPECT_NEAR(c.depthAtEnd, (p1 - sphere.center()).norm() - big, 1e-12);
      EXPECT_EQ(c.intervals.empty(), settings.mode == CcdMode::FirstHit);
      ++contacts;
    }
    EXPECT_EQ(next, r.contacts.size());
  }
  EXPECT_GT(contacts, 500);
}

TEST(RigidCcd, TreeEqualsLinearOnRandomShellsAndRandomGridFields) {
  std::mt19937 rng(8);
  int contacts = 0;
  std::int64_t treeQueries = 0;
  std::int64_t linearQueries = 0;
  for (int field = 0; field < 6; ++field) {
    const auto& [grid, tree, poses] = randomGridCase(100 + field, field, rng);
    for (int config = 0; config < 40; ++config) {
      const Rigid a = test::randomPose(poses, rng);
      // Half the steps are short (the simulation case), half span the expanded box (Table 3).
      Rigid b = test::randomPose(poses, rng);
      if (config % 2 == 0) b = shortStepFrom(a, b);
      RigidCcdSettings s = variedGridSettings(config);
      s.mode = config % 4 == 3 ? CcdMode::FirstHit : CcdMode::AllIntervals;
      s.method = config % 3 == 2 ? CcdMethod::Bisection : CcdMethod::Exact;
      const std::string what = "field " + std::to_string(field) + " config " + std::to_string(config);
      const RigidCcdResult linear = checkTreeEqualsLinear(tree, grid, a, b, s, what);
      contacts += static_cast<int>(linear.contacts.size());
      linearQueries += linear.stats.segmentQueries;
      treeQueries += run(tree, grid, a, b, s).stats.segmentQueries;
    }
  }
  EXPECT_GT(contacts, 2000);
  EXPECT_LT(treeQueries, linearQueries);  // the tree culls
}

// Brute force: every node above a point of `linear`'s contacts passes the culling test. Returns the nodes checked.
template <class Field>
int expectNoNodeCulledAboveAContact(const PointTree& tree, const Field& field, const Rigid& a, const Rigid& b,
                                    const RigidCcdSettings& s, const RigidCcdResult& linear, const std::string& what) {
  std::vector<bool> colliding(tree.pointCount(), false);
  for (const auto& c : linear.contacts) colliding[c.point] = true;
  int checked = 0;
  std::vector<int> under;
  for (int n = 0; n < tree.nodeCount(); ++n) {
    under.clear();
    tree.pointsUnder(n, under);
    if (std::none_of(under.begin(), under.end(), [&](int p) { return colliding[p]; })) continue;
    ++checked;
    EXPECT_TRUE(pointTreeNodeMayCollide(tree, field, n, a, b, s))
        << "node " << n << " culled above a contact, " << what;
  }
  return checked;
}

TEST(RigidCcd, NoNodeIsCulledAboveACollidingPoint) {
  std::mt19937 rng(17);
  const GridField grid(bumpyGrid(7, 0.05));
  const PointTree tree(test::randomShell(400, 0.5, rng), PointTreeSettings{4, 2});
  const Box3 poses = expanded(grid.grid().box(), 2.0);
  const PlaneField plane(Vec3(0.3, 1.0, -0.2), 0.1);
  int checkedNodes = 0;
  for (int config = 0; config < 30; ++config) {
    const Rigid a = test::randomPose(poses, rng);
    const Rigid b = test::randomPose(poses, rng);
    RigidCcdSettings s;
    s.sigma = config % 2 == 0 ? 0.0 : 0.03;
    s.useTree = false;
    const std::string what = "config " + std::to_string(config);
    checkedNodes += expectNoNodeCulledAboveAContact(tree, grid, a, b, s, run(tree, grid, a, b, s), what + " grid");
    checkedNodes += expectNoNodeCulledAboveAContact(tree, plane, a, b, s, run(tree, plane, a, b, s), what + " plane");
  }
  EXPECT_GT(checkedNodes, 1000);
}

// Node centres outside the field's box with points inside it (the projected-path node test): shells that
// straddle the box faces, in both kinds of steps. No node is culled above a colliding point, and the tree
// returns the linear contacts.
TEST(RigidCcd, NodesWhoseCentreLeavesTheBoxAreCulledOnlyWhenNoPointBelowTouches) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const GridField grid(bumpyGrid(11, 0.02));
  const Box3 box = grid.grid().box();
  const PointTree tree(test::randomShell(300, 0.45, rng), PointTreeSettings{3, 2});
  // A point near a random face of the box, up to 0.4 in or out.
  const auto nearFace = [&]() {
    Vec3 p = box.min() + box.sizes().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    const int axis = static_cast<int>(3.0 * u(rng)) % 3;
    p[axis] = (u(rng) < 0.5 ? box.min()[axis] : box.max()[axis]) + 0.8 * (u(rng) - 0.5);
    return p;
  };
  int contacts = 0;
  int checkedNodes = 0;
  for (int config = 0; config < 60; ++config) {
    Rigid a = test::randomPose(box, rng);
    Rigid b = test::randomPose(box, rng);
    a.translation() = nearFace();
    b.translation() = config % 2 == 0 ? nearFace() : Vec3(a.translation() + 0.1 * (b.translation() - a.translation()));
    RigidCcdSettings s;
    s.sigma = config % 3 == 0 ? 0.02 : 0.0;
    const std::string what = "config " + std::to_string(config);
    const RigidCcdResult linear = checkTreeEqualsLinear(tree, grid, a, b, s, what);
    contacts += static_cast<int>(linear.contacts.size());
    checkedNodes += expectNoNodeCulledAboveAContact(tree, grid, a, b, s, linear, what);
  }
  EXPECT_GT(contacts, 300);
  EXPECT_GT(checkedNodes, 300);
}

TEST(RigidCcd, IgnoredPointsAreSkipped) {
  std::mt19937 rng(4);
  const PointTree tree(shellFromVertices(makeIcosphere(1.0, 2)));
  const PlaneField ground = PlaneField::ground();
  Rigid a = Rigid::Identity();
  a.translation() = Vec3(0, 0.5, 0);
  Rigid b = Rigid::Identity();
  b.translation() = Vec3(0, -0.5, 0);
  RigidCcdSettings s;
  const RigidCcdResult all = run(tree, ground, a, b, s);
  ASSERT_GT(all.contacts.size(), 10u);
  std::vector<std::uint8_t> ignored(tree.pointCount(), 0);
  for (std::size_t n = 0; n < all.contacts.size(); n += 2) ignored[all.contacts[n].point] = 1;
  s.ignoredPoints = &ignored;
  for (bool useTree : {false, true}) {
    for (int threads : {1, 2}) {
      s.useTree = useTree;
      s.threads = threads;
      const RigidCcdResult some = run(tree, ground, a, b, s);
      EXPECT_EQ(some.contacts.size(), all.contacts.size() / 2);
      for (const auto& c : some.contacts) EXPECT_EQ(ignored[c.point], 0);
    }
  }
  std::vector<std::uint8_t> wrongSize(3, 0);
  s.ignoredPoints = &wrongSize;
  EXPECT_THROW(run(tree, ground, a, b, s), Error);
  s.ignoredPoints = nullptr;
  b.translation().x() = std::nan("");
  EXPECT_THROW(run(tree, ground, a, b, s), Error);
}

TEST(RigidCcd, CullingBoundsOfGrids) {
  // An exact distance to a point sampled on a grid: steeper than 1 near the point, never above sqrt(3).
  const auto grid =
      test::sampleGrid(Vec3i(9, 9, 9), Vec3::Constant(-1.0), 0.25, [](const Vec3& p) { return p.norm(); });
  const FieldCullingBounds bounds = computeCullingBounds(*grid);
  EXPECT_TRUE(bounds.bounded);
  EXPECT_GT(bounds.lipschitz, 1.0);
  EXPECT_LE(bounds.lipschitz, std::sqrt(3.0) * (1.0 + 1e-6));
  EXPECT_NEAR(bounds.boundaryMin, 1.0, 1e-6);
  // A linear field: exactly its slope.
  const auto linear = test::sampleGrid(Vec3i(5, 6, 7), Vec3::Zero(), 0.5, [](const Vec3& p) { return 0.5 * p.x(); });
  EXPECT_NEAR(computeCullingBounds(*linear).lipschitz, 0.5, 1e-6);
  EXPECT_NEAR(computeCullingBounds(*linear).boundaryMin, 0.0, 1e-12);
  const GridField field(grid);
  EXPECT_EQ(fieldCullingBounds(field).lipschitz, bounds.lipschitz);  // cached
  EXPECT_EQ(fieldCullingBounds(PlaneField::ground()).lipschitz, 1.0);
}

// The scanned models of the paper vs their own fields, at a low resolution.
void checkModel(const std::string& file, int points, int configs) {
  TriangleMesh mesh = test::readOff(std::string(SDFCCD_ASSETS_DIR) + "/meshes/" + file);
  repairMesh(mesh);
  SdfBuildSettings build;
  build.resolution = 32;
  build.threads = 2;
  const GridField field(buildSdf(mesh, build).grid);
  ShellSamplingSettings sampling;
  sampling.points = points;
  sampling.iterations = 5;
  // The shell's frame is centred on the mesh's box, so poses in the expanded box place the shell around it.
  PointShell shell = sampleShell(mesh, sampling);
  const Vec3 centre = mesh.bounds().center();
  for (auto& p : shell.positions) p -= centre;
  const PointTree tree(shell);
  const Box3 poses = expanded(field.grid().box(), 3.0);
  std::mt19937 rng(1);
  int contacts = 0;
  for (int config = 0; config < configs; ++config) {
    const Rigid a = test::randomPose(poses, rng);
    const Rigid b = test::randomPose(poses, rng);
    RigidCcdSettings s;
    contacts += static_cast<int>(
        checkTreeEqualsLinear(tree, field, a, b, s, file + " config " + std::to_string(config)).contacts.size());
  }
  EXPECT_GT(contacts, 0) << file;
}

TEST(RigidCcd, BunnyShellEqualsLinearAgainstTheBunnyField) {
  checkModel("bunny.off", 777, 60);
}

TEST(RigidCcd, DragonShellEqualsLinearAgainstTheDragonField) {
  checkModel("dragon.off", 3000, 30);
}

}  // namespace
}  // namespace sdfccd
