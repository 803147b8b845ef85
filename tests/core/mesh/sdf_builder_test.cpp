/// @file
/// @brief buildSdf against analytic and brute-force distances at every node (Section 5, Table 1 fields).
#include "sdfccd/mesh/sdf_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/sdf_test_meshes.h"
#include "sdfccd/error.h"

namespace sdfccd {
namespace {

/// The SDF of `mesh` at `resolution` cells along its longest side with `padding` cells around, default threads.
SdfBuildResult buildSdfAt(const TriangleMesh& mesh, int resolution, int padding) {
  SdfBuildSettings settings;
  settings.resolution = resolution;
  settings.padding = padding;
  return buildSdf(mesh, settings);
}

Vec3 nodePosition(const SdfGrid& g, int i, int j, int k) {
  return g.origin() + g.spacing() * Vec3(i, j, k);
}

// Float storage of a double: agreement "to float rounding".
double floatTolerance(double reference) {
  return 2e-7 * std::max(1.0, std::fabs(reference)) + 1e-12;
}

template <class F>
void forEachNode(const SdfGrid& g, F&& f) {
  for (int k = 0; k < g.nodeCounts().z(); ++k)
    for (int j = 0; j < g.nodeCounts().y(); ++j)
      for (int i = 0; i < g.nodeCounts().x(); ++i) f(i, j, k, nodePosition(g, i, j, k), g.value(i, j, k));
}

TEST(SdfBuilder, BoxIsExactAtEveryNode) {
  const Vec3 h(0.5, 0.3, 0.4);
  const TriangleMesh mesh = test::boxMesh(h);
  ASSERT_GT(mesh.signedVolume(), 0.0);
  ASSERT_TRUE(isClosedAndOriented(mesh));
  const SdfBuildResult r = buildSdfAt(mesh, 20, 3);
  EXPECT_EQ(r.stats.signMethod, SdfSignMethod::Pseudonormal);
  const SdfGrid& g = *r.grid;
  EXPECT_EQ(g.nodeCounts(), Vec3i(27, 19, 23));  // 20 + 6 cells along x; ceil(12) + 6, ceil(16) + 6
  EXPECT_NEAR(g.spacing(), 0.05, 1e-15);
  int checked = 0;
  forEachNode(g, [&](int, int, int, const Vec3& p, float v) {
    const double reference = test::boxSignedDistance(p, h);
    ASSERT_NEAR(v, reference, floatTolerance(reference)) << p.transpose();
    ++checked;
  });
  EXPECT_EQ(checked, 27 * 19 * 23);
}

TEST(SdfBuilder, TetrahedronIsExactWithTheRightSignEverywhere) {
  const TriangleMesh mesh = test::tetrahedronMesh();
  const SdfBuildResult built1 = buildSdfAt(mesh, 24, 4);
  const SdfGrid& g = *built1.grid;
  // Inside a convex polyhedron: behind every face plane.
  auto inside = [&](const Vec3& p) {
    for (const auto& t : mesh.triangles) {
      const Vec3& a = mesh.vertices[t[0]];
      const Vec3 n = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a);
      if ((p - a).dot(n) >= 0.0) return false;
    }
    return true;
  };
  forEachNode(g, [&](int, int, int, const Vec3& p, float v) {
    const double d = test::bruteForceDistance(mesh, p);
    const double reference = inside(p) ? -d : d;
    ASSERT_NEAR(v, reference, floatTolerance(reference)) << p.transpose();
  });
}

TEST(SdfBuilder, IcosphereMatchesBruteForceAndTheSphere) {
  const double radius = 0.7;
  const TriangleMesh mesh = test::icosphereMesh(radius, 2);  // 320 triangles
  ASSERT_TRUE(isClosedAndOriented(mesh));
  SdfBuildSettings settings;
  settings.resolution = 16;
  settings.padding = 3;
  settings.threads = 2;
  const SdfBuildResult built2 = buildSdf(mesh, settings);
  const SdfGrid& g = *built2.grid;
  // Tessellation error: the faces lie between the inscribed radius and the sphere.
  double inscribed = radius;
  for (const auto& t : mesh.triangles) {
    inscribed = std::min(
        inscribed, test::triangleDistance(Vec3::Zero(), mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
  }
  const double tessellation = radius - inscribed;
  forEachNode(g, [&](int, int, int, const Vec3& p, float v) {
    const double d = test::bruteForceDistance(mesh, p);
    // Convex: inside iff behind every face plane; the brute force sign.
    bool in = true;
    for (const auto& t : mesh.triangles) {
      const Vec3& a = mesh.vertices[t[0]];
      in = in && (p - a).dot((mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a)) < 0.0;
    }
    const double reference = in ? -d : d;
    ASSERT_NEAR(v, reference, floatTolerance(reference)) << p.transpose();
    ASSERT_NEAR(v, p.norm() - radius, tessellation + 1e-6) << p.transpose();
  });
}

TEST(SdfBuilder, FastBuilderAgreesWithBruteForceOnARealMesh) {
  const TriangleMesh mesh = test::readOff(std::string(SDFCCD_ASSETS_DIR) + "/meshes/knot1.off");
  ASSERT_TRUE(isClosedAndOriented(mesh));
  SdfBuildSettings settings;
  settings.resolution = 10;
  settings.padding = 1;
  const SdfBuildResult built3 = buildSdf(mesh, settings);
  const SdfGrid& g = *built3.grid;
  settings.signMethod = SdfSignMethod::WindingNumber;
  const SdfBuildResult built4 = buildSdf(mesh, settings);
  const SdfGrid& w = *built4.grid;
  int signDisagreements = 0;
  forEachNode(g, [&](int i, int j, int k, const Vec3& p, float v) {
    const double d = test::bruteForceDistance(mesh, p);
    ASSERT_NEAR(std::fabs(v), d, floatTolerance(d)) << p.transpose();
    ASSERT_EQ(std::fabs(w.value(i, j, k)), std::fabs(v));
    signDisagreements += (w.value(i, j, k) < 0.0f) != (v < 0.0f) ? 1 : 0;
  });
  // On a closed mesh both sign methods agree (up to the winding number's far-field error right at the surface).
  EXPECT_LE(signDisagreements, 0);
}

TEST(SdfBuilder, ThreadCountDoesNotChangeTheResult) {
  const TriangleMesh mesh = test::icosphereMesh(1.0, 3);
  SdfBuildSettings settings;
  settings.resolution = 20;
  settings.threads = 1;
  const SdfBuildResult one = buildSdf(mesh, settings);
  settings.threads = 2;
  const SdfBuildResult two = buildSdf(mesh, settings);
  EXPECT_EQ(one.grid->values(), two.grid->values());
  EXPECT_EQ(two.stats.threads, 2);
  EXPECT_EQ(two.stats.gridBytes, two.grid->values().size() * sizeof(float));
}

TEST(SdfBuilder, FlippedFacesAreRepairedBeforeBuilding) {
  const Vec3 h(0.4, 0.4, 0.25);
  TriangleMesh mesh = test::boxMesh(h);
  std::swap(mesh.triangles[2][1], mesh.triangles[2][2]);
  std::swap(mesh.triangles[7][1], mesh.triangles[7][2]);
  EXPECT_FALSE(isClosedAndOriented(mesh));
  const MeshRepairReport report = repairMesh(mesh);
  EXPECT_EQ(report.reorientedFaces, 2);
  EXPECT_TRUE(report.closed);
  SdfBuildSettings settings;
  settings.resolution = 12;
  const SdfBuildResult built5 = buildSdf(mesh, settings);
  const SdfGrid& g = *built5.grid;
  forEachNode(g, [&](int, int, int, const Vec3& p, float v) {
    const double reference = test::boxSignedDistance(p, h);
    ASSERT_NEAR(v, reference, floatTolerance(reference));
  });
}

TEST(SdfBuilder, MeshWithAHoleGetsASensibleSign) {
  // A sphere with the triangles around one pole removed: open, so the winding number decides.
  const double radius = 1.0;
  TriangleMesh mesh = test::icosphereMesh(radius, 2);
  const Vec3 pole = Vec3(0.0, 1.0, 0.0);
  std::vector<std::array<int, 3>> kept;
  for (const auto& t : mesh.triangles) {
    const Vec3 centroid = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
    if (centroid.normalized().dot(pole) < 0.95) kept.push_back(t);
  }
  ASSERT_LT(kept.size(), mesh.triangles.size());
  mesh.triangles = kept;
  const MeshRepairReport report = repairMesh(mesh);
  EXPECT_FALSE(report.closed);
  EXPECT_GT(report.boundaryEdges, 0);
  const SdfBuildResult r = buildSdfAt(mesh, 16, 3);
  EXPECT_EQ(r.stats.signMethod, SdfSignMethod::WindingNumber);
  const SdfGrid& g = *r.grid;
  int checkedInside = 0, checkedOutside = 0;
  forEachNode(g, [&](int, int, int, const Vec3& p, float v) {
    const double d = test::bruteForceDistance(mesh, p);
    ASSERT_NEAR(std::fabs(v), d, floatTolerance(d));
    // Far from the hole (more than a third of the radius away from the pole cap), the sphere's sign holds.
    if ((p - radius * pole).norm() < 0.8 || d < 1e-9) return;
    if (p.norm() < 0.9 * radius) {
      EXPECT_LT(v, 0.0f) << p.transpose();
      ++checkedInside;
    } else if (p.norm() > 1.05 * radius) {
      EXPECT_GT(v, 0.0f) << p.transpose();
      ++checkedOutside;
    }
  });
  EXPECT_GT(checkedInside, 100);
  EXPECT_GT(checkedOutside, 100);
}

TEST(SdfBuilder, OpenSheetIsUnsignedFarAwayAndExact) {
  // A single square (two triangles): open, no inside; every node is outside (w ~ 0 or the jump is < 1/2).
  TriangleMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  const SdfBuildResult built6 = buildSdfAt(mesh, 8, 2);
  const SdfGrid& g = *built6.grid;
  EXPECT_EQ(g.nodeCounts().z(), 6);  // a flat mesh still gets one cell plus padding across
  forEachNode(g, [&](int, int, int, const Vec3& p, float v) {
    const double d = test::bruteForceDistance(mesh, p);
    ASSERT_NEAR(v, d, floatTolerance(d)) << p.transpose();
  });
}

TEST(SdfBuilder, RejectsBadInputAndSettings) {
  const TriangleMesh box = test::boxMesh(Vec3(1, 1, 1));
  SdfBuildSettings settings;
  settings.resolution = 0;
  EXPECT_THROW(buildSdf(box, settings), Error);
  settings.resolution = 5000;
  EXPECT_THROW(buildSdf(box, settings), Error);
  settings.resolution = 16;
  settings.padding = -1;
  EXPECT_THROW(buildSdf(box, settings), Error);
  settings.padding = 2;
  settings.maxMemoryBytes = 1000;  // refused before allocating
  EXPECT_THROW(buildSdf(box, settings), Error);
  settings.maxMemoryBytes = std::size_t(1) << 30;
  EXPECT_THROW(buildSdf(TriangleMesh{}, settings), Error);
  TriangleMesh bad = box;
  bad.vertices[3].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(buildSdf(bad, settings), Error);
  bad = box;
  bad.triangles[0][1] = 99;
  EXPECT_THROW(buildSdf(bad, settings), Error);
  try {
    settings.resolution = 4096;
    settings.maxMemoryBytes = std::size_t(64) << 20;
    buildSdf(box, settings);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("MiB"), std::string::npos);
  }
}

TEST(SdfBuilder, ReportsProgressUpToOne) {
  const TriangleMesh mesh = test::icosphereMesh(1.0, 2);
  SdfBuildSettings settings;
  settings.resolution = 24;
  double last = -1.0;
  int calls = 0;
  bool monotone = true;
  settings.progress = [&](double f) {
    monotone = monotone && f >= last - 1e-12;
    last = f;
    ++calls;
  };
  buildSdf(mesh, settings);
  EXPECT_GT(calls, 1);
  EXPECT_DOUBLE_EQ(last, 1.0);
  EXPECT_TRUE(monotone);
}

// Two closed boxes in one mesh: box (centre, half sizes) as 12 outward triangles, vertices offset by `base`.
void appendBox(TriangleMesh& mesh, const Vec3& centre, const Vec3& half) {
  const TriangleMesh box = test::boxMesh(half);
  const int base = static_cast<int>(mesh.vertices.size());
  for (const Vec3& v : box.vertices) mesh.vertices.push_back(v + centre);
  for (const auto& t : box.triangles) mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

// Brute-force check of a field of a union of boxes: at every node, |value| is the distance to the triangle set
// and the sign says whether the node is inside some box (nodes within 1e-9 of a box surface are skipped).
void expectUnionOfBoxes(const TriangleMesh& mesh, const SdfGrid& g, const std::vector<std::pair<Vec3, Vec3>>& boxes,
                        std::size_t& insideNodes) {
  std::size_t wrongSign = 0;
  insideNodes = 0;
  forEachNode(g, [&](int, int, int, const Vec3& p, double value) {
    double nearest = std::numeric_limits<double>::infinity();
    bool inside = false;
    for (const auto& [centre, half] : boxes) {
      const double d = test::boxSignedDistance(p - centre, half);
      nearest = std::min(nearest, std::fabs(d));
      inside = inside || d < 0.0;
    }
    if (nearest < 1e-9) return;
    const double distance = test::bruteForceDistance(mesh, p);
    EXPECT_NEAR(std::fabs(value), distance, floatTolerance(distance));
    insideNodes += inside ? 1 : 0;
    if ((value < 0.0) != inside) ++wrongSign;
  });
  EXPECT_EQ(wrongSign, 0u) << "of " << insideNodes << " inside nodes";
}

// A closed mesh that intersects itself (two overlapping cubes in one file). The faces of each cube inside the other
// are buried; nodes closest to them get a positive pseudonormal sign. The automatic sign detects the crossing
// triangles and uses the winding number: every node inside the union is negative.
TEST(SdfBuilder, SelfIntersectingCubesAreSignedAsTheirUnion) {
  const std::vector<std::pair<Vec3, Vec3>> boxes = {{Vec3(0.0, 0.0, 0.0), Vec3(0.5, 0.5, 0.5)},
                                                    {Vec3(0.37, 0.21, 0.13), Vec3(0.45, 0.5, 0.4)}};
  TriangleMesh mesh;
  for (const auto& [centre, half] : boxes) appendBox(mesh, centre, half);
  ASSERT_TRUE(isClosedAndOriented(mesh));
  SdfBuildSettings settings;
  settings.resolution = 20;
  settings.padding = 2;
  const SdfBuildResult automatic = buildSdf(mesh, settings);
  EXPECT_EQ(automatic.stats.signMethod, SdfSignMethod::WindingNumber);
  EXPECT_GT(automatic.stats.selfIntersections, 0u);
  std::size_t insideNodes = 0;
  expectUnionOfBoxes(mesh, *automatic.grid, boxes, insideNodes);
  EXPECT_GT(insideNodes, 1000u);
  // The pseudonormal, when asked for explicitly, still gives the buried faces' nodes the wrong sign: the case
  // the automatic choice avoids.
  settings.signMethod = SdfSignMethod::Pseudonormal;
  const SdfBuildResult pseudonormal = buildSdf(mesh, settings);
  std::size_t positiveInside = 0;
  forEachNode(*pseudonormal.grid, [&](int, int, int, const Vec3& p, double value) {
    bool deepInside = false;
    for (const auto& [centre, half] : boxes)
      deepInside = deepInside || test::boxSignedDistance(p - centre, half) < -1e-9;
    if (deepInside && value > 0.0) ++positiveInside;
  });
  EXPECT_GT(positiveInside, 0u);
}

// Nested shells of one orientation do not cross, but the pseudonormal of the inner shell says "outside" in
// the gap; the block check against the winding number catches it and the whole field is the solid outer box.
TEST(SdfBuilder, NestedShellsOfOneOrientationAreSignedByTheWindingNumber) {
  const std::vector<std::pair<Vec3, Vec3>> boxes = {{Vec3::Zero(), Vec3(2.0, 2.0, 2.0)},
                                                    {Vec3(0.1, 0.0, -0.2), Vec3(0.5, 0.5, 0.5)}};
  TriangleMesh mesh;
  for (const auto& [centre, half] : boxes) appendBox(mesh, centre, half);
  SdfBuildSettings settings;
  settings.resolution = 40;
  settings.padding = 2;
  const SdfBuildResult result = buildSdf(mesh, settings);
  EXPECT_EQ(result.stats.selfIntersections, 0u);
  EXPECT_GT(result.stats.inconsistentSignNodes, 0u);
  EXPECT_EQ(result.stats.signMethod, SdfSignMethod::WindingNumber);
  std::size_t insideNodes = 0;
  expectUnionOfBoxes(mesh, *result.grid, boxes, insideNodes);
}

// A closed mesh without crossings or nested shells keeps the exact, cheap pseudonormal sign.
TEST(SdfBuilder, AutomaticSignKeepsThePseudonormalOnCleanClosedMeshes) {
  const SdfBuildResult result = buildSdfAt(test::icosphereMesh(1.0, 2), 24, 2);
  EXPECT_EQ(result.stats.signMethod, SdfSignMethod::Pseudonormal);
  EXPECT_EQ(result.stats.selfIntersections, 0u);
  EXPECT_EQ(result.stats.inconsistentSignNodes, 0u);
}

}  // namespace
}  // namespace sdfccd
