/// @file
/// @brief TriangleMesh measures and repairMesh: exact repair counts on constructed inputs.
#include "sdfccd/mesh/triangle_mesh.h"

#include <gtest/gtest.h>

#include <limits>

#include "core/sdf_test_meshes.h"
#include "sdfccd/error.h"

namespace sdfccd {
namespace {

// A unit cube [0,1]^3 as 6 separate quads (4 own vertices each): a typical "soup" from STL-like files.
TriangleMesh cubeSoup() {
  TriangleMesh m;
  const TriangleMesh box = test::boxMesh(Vec3(0.5, 0.5, 0.5));
  for (const auto& t : box.triangles) {
    const int base = static_cast<int>(m.vertices.size());
    for (int c = 0; c < 3; ++c) m.vertices.push_back(box.vertices[t[c]] + Vec3(0.5, 0.5, 0.5));
    m.triangles.push_back({base, base + 1, base + 2});
  }
  return m;
}

TEST(TriangleMesh, MeasuresOfAUnitCube) {
  TriangleMesh cube = test::boxMesh(Vec3(0.5, 0.5, 0.5));
  EXPECT_NEAR(cube.signedVolume(), 1.0, 1e-15);
  EXPECT_NEAR(cube.area(), 6.0, 1e-15);
  EXPECT_TRUE(cube.bounds().min().isApprox(Vec3(-0.5, -0.5, -0.5)));
  EXPECT_TRUE(cube.bounds().max().isApprox(Vec3(0.5, 0.5, 0.5)));
  EXPECT_TRUE(TriangleMesh{}.bounds().isEmpty());
}

TEST(RepairMesh, CleanClosedMeshIsUnchanged) {
  TriangleMesh cube = test::boxMesh(Vec3(1, 2, 3));
  const TriangleMesh before = cube;
  const MeshRepairReport r = repairMesh(cube);
  EXPECT_EQ(r.mergedVertices, 0);
  EXPECT_EQ(r.droppedDegenerate, 0);
  EXPECT_EQ(r.droppedDuplicates, 0);
  EXPECT_EQ(r.reorientedFaces, 0);
  EXPECT_EQ(r.unreferencedVertices, 0);
  EXPECT_EQ(r.boundaryEdges, 0);
  EXPECT_EQ(r.nonManifoldEdges, 0);
  EXPECT_EQ(r.components, 1);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(cube.triangles, before.triangles);
  EXPECT_EQ(r.summary(), "no repairs; 1 component, closed");
}

TEST(RepairMesh, MergesDuplicateVerticesOfASoup) {
  TriangleMesh soup = cubeSoup();
  ASSERT_EQ(soup.vertices.size(), 36u);
  const MeshRepairReport r = repairMesh(soup);
  EXPECT_EQ(r.mergedVertices, 28);
  EXPECT_EQ(soup.vertices.size(), 8u);
  EXPECT_EQ(soup.triangles.size(), 12u);
  EXPECT_TRUE(r.closed);
  EXPECT_NEAR(soup.signedVolume(), 1.0, 1e-15);
}

TEST(RepairMesh, MergesWithinATolerance) {
  TriangleMesh soup = cubeSoup();
  soup.vertices[5] += Vec3(1e-9, -1e-9, 0.0);
  TriangleMesh exact = soup;
  EXPECT_FALSE(repairMesh(exact).closed);  // the nudged vertex does not merge exactly
  MeshRepairSettings settings;
  settings.mergeTolerance = 1e-6;
  const MeshRepairReport r = repairMesh(soup, settings);
  EXPECT_EQ(r.mergedVertices, 28);
  EXPECT_TRUE(r.closed);
}

TEST(RepairMesh, DropsDegenerateAndDuplicateFacesAndUnreferencedVertices) {
  TriangleMesh m = test::boxMesh(Vec3(1, 1, 1));
  m.triangles.push_back({0, 0, 1});  // repeated index
  m.vertices.push_back(Vec3(2, 0, 0));
  m.vertices.push_back(Vec3(3, 0, 0));
  m.vertices.push_back(Vec3(4, 0, 0));
  m.triangles.push_back({8, 9, 10});                                                 // collinear: zero area
  m.triangles.push_back(m.triangles[0]);                                             // exact duplicate
  m.triangles.push_back({m.triangles[1][0], m.triangles[1][2], m.triangles[1][1]});  // duplicate, flipped
  m.vertices.push_back(Vec3(7, 7, 7));                                               // used by nothing
  const MeshRepairReport r = repairMesh(m);
  EXPECT_EQ(r.droppedDegenerate, 2);
  EXPECT_EQ(r.droppedDuplicates, 2);
  EXPECT_EQ(r.unreferencedVertices, 4);  // the three collinear ones and the lonely one
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_TRUE(r.closed);
  EXPECT_NE(r.summary().find("dropped degenerate faces 2"), std::string::npos);
}

TEST(RepairMesh, OrientsFlippedFacesAndInsideOutComponents) {
  TriangleMesh m = test::boxMesh(Vec3(1, 1, 1));
  std::swap(m.triangles[0][1], m.triangles[0][2]);
  std::swap(m.triangles[5][1], m.triangles[5][2]);
  std::swap(m.triangles[9][1], m.triangles[9][2]);
  MeshRepairReport r = repairMesh(m);
  EXPECT_EQ(r.reorientedFaces, 3);
  EXPECT_TRUE(r.closed);
  EXPECT_NEAR(m.signedVolume(), 8.0, 1e-12);

  TriangleMesh inverted = test::boxMesh(Vec3(1, 1, 1));
  for (auto& t : inverted.triangles) std::swap(t[1], t[2]);
  r = repairMesh(inverted);
  EXPECT_EQ(r.reorientedFaces, 12);
  EXPECT_NEAR(inverted.signedVolume(), 8.0, 1e-12);

  MeshRepairSettings keep;
  keep.orient = false;
  TriangleMesh flipped = test::boxMesh(Vec3(1, 1, 1));
  std::swap(flipped.triangles[3][1], flipped.triangles[3][2]);
  r = repairMesh(flipped, keep);
  EXPECT_EQ(r.reorientedFaces, 0);
  EXPECT_FALSE(r.closed);  // inconsistent orientation: pseudonormals would not be exact
}

TEST(RepairMesh, CountsBoundaryNonManifoldEdgesAndComponents) {
  TriangleMesh open = test::boxMesh(Vec3(1, 1, 1));
  open.triangles.erase(open.triangles.begin(), open.triangles.begin() + 2);  // remove the -z face
  MeshRepairReport r = repairMesh(open);
  EXPECT_EQ(r.boundaryEdges, 4);
  EXPECT_EQ(r.nonManifoldEdges, 0);
  EXPECT_FALSE(r.closed);
  EXPECT_NE(r.summary().find("open (4 boundary edges"), std::string::npos);

  TriangleMesh fan;  // three triangles on one edge
  fan.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)};
  fan.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  r = repairMesh(fan);
  EXPECT_EQ(r.nonManifoldEdges, 1);
  EXPECT_EQ(r.boundaryEdges, 6);
  EXPECT_EQ(r.components, 1);
  EXPECT_FALSE(r.closed);

  TriangleMesh two = test::boxMesh(Vec3(1, 1, 1));
  const TriangleMesh other = test::boxMesh(Vec3(0.5, 0.5, 0.5));
  for (const Vec3& v : other.vertices) two.vertices.push_back(v + Vec3(5, 0, 0));
  for (const auto& t : other.triangles) two.triangles.push_back({t[0] + 8, t[2] + 8, t[1] + 8});  // inside out
  r = repairMesh(two);
  EXPECT_EQ(r.components, 2);
  EXPECT_EQ(r.reorientedFaces, 12);
  EXPECT_TRUE(r.closed);
  EXPECT_NEAR(two.signedVolume(), 9.0, 1e-12);
}

TEST(RepairMesh, RejectsEmptyNonFiniteAndBrokenInput) {
  TriangleMesh empty;
  EXPECT_THROW(repairMesh(empty), Error);
  TriangleMesh nan = test::boxMesh(Vec3(1, 1, 1));
  nan.vertices[2].y() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(repairMesh(nan), Error);
  TriangleMesh bad = test::boxMesh(Vec3(1, 1, 1));
  bad.triangles[4][0] = -1;
  EXPECT_THROW(repairMesh(bad), Error);
  TriangleMesh degenerate;
  degenerate.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  degenerate.triangles = {{0, 1, 2}, {0, 0, 1}};
  try {
    repairMesh(degenerate);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

}  // namespace
}  // namespace sdfccd
