/// @file
/// @brief Point shells of an open mesh loaded from the assets (mech-holes-shark.off, which has holes): the
/// vertex shell and the repulsion samples lie on the mesh with unit normals, and the tree over them is sound.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/io/mesh_loader.h"
#include "sdfccd/shell/point_shell.h"
#include "sdfccd/shell/point_tree.h"

namespace sdfccd {
namespace {

double segmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (a + t * d - p).norm();
}

// Brute force distance to the mesh: plane distance inside a face, else the nearest edge.
double meshDistance(const TriangleMesh& mesh, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[t[0]];
    const Vec3& b = mesh.vertices[t[1]];
    const Vec3& c = mesh.vertices[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    const double n2 = n.squaredNorm();
    if (n2 > 0.0) {
      const Vec3 q = p - (p - a).dot(n) / n2 * n;
      if ((b - a).cross(q - a).dot(n) >= 0.0 && (c - b).cross(q - b).dot(n) >= 0.0 &&
          (a - c).cross(q - c).dot(n) >= 0.0) {
        best = std::min(best, (p - q).norm());
        continue;
      }
    }
    best = std::min({best, segmentDistance(p, a, b), segmentDistance(p, b, c), segmentDistance(p, c, a)});
  }
  return best;
}

TEST(PointShellOpenMesh, SharkWithHolesGivesShellsOnItsSurface) {
  MeshRepairReport report;
  const TriangleMesh mesh = loadMesh(std::string(SDFCCD_ASSETS_DIR) + "/meshes/mech-holes-shark.off", &report);
  EXPECT_FALSE(report.closed);
  EXPECT_GT(report.boundaryEdges, 0);

  const PointShell vertices = shellFromVertices(mesh);
  vertices.validate();
  EXPECT_GT(vertices.size(), mesh.vertices.size() / 2);

  ShellSamplingSettings settings;
  settings.points = 300;
  settings.iterations = 10;
  const PointShell sampled = sampleShell(mesh, settings);
  ASSERT_EQ(sampled.size(), 300u);
  sampled.validate();
  const double scale = mesh.bounds().sizes().norm();
  for (const auto& p : sampled.positions) EXPECT_LT(meshDistance(mesh, p), 1e-12 * scale);

  // The tree over the open shell: tree == linear against a plane cutting through it.
  const PointTree tree(sampled);
  const PlaneField plane(Vec3(0.2, 1.0, 0.1), mesh.bounds().center().y());
  Rigid a = Rigid::Identity();
  a.translation() = Vec3(0.0, 0.3 * scale, 0.0);
  Rigid b = Rigid::Identity();
  b.translation() = Vec3(0.0, -0.1 * scale, 0.0);
  RigidCcdSettings s;
  RigidCcdResult linear;
  RigidCcdResult treeResult;
  s.useTree = false;
  rigidCcd(tree, plane, a, b, s, linear);
  s.useTree = true;
  rigidCcd(tree, plane, a, b, s, treeResult);
  ASSERT_GT(linear.contacts.size(), 0u);
  ASSERT_EQ(linear.contacts.size(), treeResult.contacts.size());
  for (std::size_t n = 0; n < linear.contacts.size(); ++n) {
    EXPECT_EQ(linear.contacts[n].point, treeResult.contacts[n].point);
    EXPECT_EQ(linear.contacts[n].fraction, treeResult.contacts[n].fraction);
  }
}

}  // namespace
}  // namespace sdfccd
