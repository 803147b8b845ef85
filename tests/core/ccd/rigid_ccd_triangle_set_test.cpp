// The point tree against a TriangleSetField (an open mesh: Bullet's triangle meshes and terrain): the field is not
// 1-Lipschitz (it jumps by up to twice its thickness at a slab's back face and across an open edge), so the tree's
// culling needs its stated jump; with it the tree returns exactly the point-by-point query's contacts, also on a
// ridge and behind its open edges.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "core/ccd/rigid_ccd_test_util.h"
#include "sdfccd/field/field_interface.h"
#include "sdfccd/field/polytope_fields.h"

namespace sdfccd {
namespace rigid_ccd_triangle_set_test {

/// A roof: two 2 x 1 slopes meeting at a ridge along z (y = 0.5 at x = 0), open at every edge, seen from above.
TriangleSetField roof(double radius, double thickness) {
  const std::vector<Vec3> v = {{-1, 0, -1}, {-1, 0, 1}, {0, 0.5, -1}, {0, 0.5, 1}, {1, 0, -1}, {1, 0, 1}};
  return TriangleSetField(v, {{0, 1, 3}, {0, 3, 2}, {2, 3, 5}, {2, 5, 4}}, radius, thickness, Vec3(0, 3, 0));
}

// phi(q) >= phi(p) - |p - q| - jump for any p, q (brute force over random pairs, many of them straddling the
// slabs' back faces and the open edges), and the jump is reached: a 1-Lipschitz bound alone does not hold.
TEST(RigidCcdTriangleSet, JumpBoundsTheFieldsDrop) {
  const double thickness = 0.2;
  const TriangleSetField field = roof(0.02, thickness);
  const FieldCullingBounds bounds = fieldCullingBounds(field);
  EXPECT_EQ(bounds.jump, 2.0 * thickness);
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-1.3, 1.3);
  std::normal_distribution<double> g(0.0, 0.05);
  double largestDrop = 0.0;  // largest phi(p) - |p - q| - phi(q) seen
  for (int i = 0; i < 200000; ++i) {
    const Vec3 p(u(rng), 0.25 + 0.5 * u(rng), u(rng));
    const Vec3 q = p + Vec3(g(rng), g(rng), g(rng));
    const double drop = field.distance(p) - (p - q).norm() - field.distance(q);
    largestDrop = std::max(largestDrop, drop);
  }
  EXPECT_LE(largestDrop, bounds.jump + 1e-12);
  EXPECT_GT(largestDrop, 0.5 * bounds.jump);  // the field does jump: the bound is needed
}

// Where jumpReachable says no jump is within reach, phi(q) >= phi(p) - lipschitz |p - q| (lipschitz 3: a point in
// front of a face sees the slab only as deep as it is far from it); 1-Lipschitz alone fails there.
TEST(RigidCcdTriangleSet, LipschitzHoldsWhereNoJumpIsReachable) {
  const TriangleSetField field = roof(0.02, 0.2);
  const FieldCullingBounds bounds = fieldCullingBounds(field);
  EXPECT_EQ(bounds.lipschitz, 3.0);
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> u(-1.3, 1.3);
  std::normal_distribution<double> g(0.0, 0.05);
  double largestExcess = -1.0;    // largest phi(p) - lipschitz |p - q| - phi(q)
  double largestPlainDrop = 0.0;  // largest phi(p) - |p - q| - phi(q)
  int checked = 0;
  for (int i = 0; i < 200000; ++i) {
    const Vec3 p(u(rng), 0.25 + 0.5 * u(rng), u(rng));
    const Vec3 q = p + Vec3(g(rng), g(rng), g(rng));
    const double r = (p - q).norm();
    if (field.jumpReachable(p, p, r)) continue;
    ++checked;
    largestExcess = std::max(largestExcess, field.distance(p) - bounds.lipschitz * r - field.distance(q));
    largestPlainDrop = std::max(largestPlainDrop, field.distance(p) - r - field.distance(q));
  }
  EXPECT_GT(checked, 50000);
  EXPECT_LE(largestExcess, 1e-12);
  EXPECT_GT(largestPlainDrop, 1e-3);  // near the open edges a 1-Lipschitz bound would cull contacts
}

// Random shells swept past the roof (above it, through it, behind its slopes and around its open edges): the tree
// equals the linear traversal bit for bit, on one and two threads, first hit and every interval.
TEST(RigidCcdTriangleSet, TreeEqualsLinearAroundARidgeAndOpenEdges) {
  const TriangleSetField field = roof(0.02, 0.2);
  std::mt19937 rng(32);
  const Box3 poses(Vec3(-1.3, -0.4, -1.3), Vec3(1.3, 0.9, 1.3));
  int contacts = 0;
  for (int config = 0; config < 60; ++config) {
    PointTreeSettings treeSettings;
    treeSettings.branching = 2 + 3 * (config % 3);
    const PointTree tree(test::randomShell(400, 0.35, rng), treeSettings);
    const Rigid a = test::randomPose(poses, rng);
    Rigid b = test::randomPose(poses, rng);
    if (config % 2 == 0) b = test::shortStepFrom(a, b);
    RigidCcdSettings s;
    s.sigma = config % 3 == 0 ? 0.01 : 0.0;
    s.mode = config % 4 == 3 ? CcdMode::FirstHit : CcdMode::AllIntervals;
    const RigidCcdResult linear = test::checkTreeEqualsLinear(tree, field, a, b, s, "config " + std::to_string(config));
    contacts += static_cast<int>(linear.contacts.size());
  }
  EXPECT_GT(contacts, 500);
}

}  // namespace rigid_ccd_triangle_set_test
}  // namespace sdfccd
