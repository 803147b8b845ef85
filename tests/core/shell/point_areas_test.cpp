/// @file
/// @brief Point areas of shells (stiffness per unit area, point_shell.h): every builder's areas sum to the surface's
/// area (meshes: TriangleMesh::area(); analytic shapes: the closed forms), vertex areas are barycentric, loaded shells
/// get theirs from assignUniformAreas, and validate() rejects bad areas.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sdfccd/error.h"
#include "sdfccd/mesh/procedural_meshes.h"
#include "sdfccd/shell/analytic_shells.h"
#include "sdfccd/shell/point_shell.h"

namespace sdfccd {
namespace {

void expectAreasSumTo(const PointShell& shell, double expected) {
  ASSERT_TRUE(shell.hasAreas());
  EXPECT_NO_THROW(shell.validate());
  EXPECT_NEAR(shell.totalArea(), expected, 1e-12 * expected);
}

TEST(PointAreas, VertexShellsSumToTheMeshArea) {
  const TriangleMesh box = makeBox(Vec3(0.3, 0.5, 0.7));
  expectAreasSumTo(shellFromVertices(box), 8.0 * (0.3 * 0.5 + 0.5 * 0.7 + 0.3 * 0.7));
  const TriangleMesh sphere = makeIcosphere(0.8, 3);
  expectAreasSumTo(shellFromVertices(sphere), sphere.area());
}

TEST(PointAreas, UnitCubeVertexAreasAreAThirdOfTheIncidentTriangles) {
  const TriangleMesh cube = makeBox(Vec3::Constant(0.5));
  const PointShell shell = shellFromVertices(cube);
  ASSERT_EQ(shell.size(), 8u);
  ASSERT_EQ(cube.vertices.size(), 8u);
  for (std::size_t v = 0; v < 8; ++v) {
    int incident = 0;  // every triangle of the unit cube has area 1/2
    for (const auto& t : cube.triangles) incident += (t[0] == int(v)) + (t[1] == int(v)) + (t[2] == int(v));
    // Three faces meet at a corner: 3 to 6 triangles, so 1/2 to 1 of area.
    EXPECT_GE(incident, 3);
    EXPECT_LE(incident, 6);
    EXPECT_NEAR(shell.areas[v], incident * 0.5 / 3.0, 1e-15) << v;
  }
  EXPECT_NEAR(shell.totalArea(), 6.0, 1e-14);
}

TEST(PointAreas, SampledShellsShareTheMeshAreaEvenly) {
  const TriangleMesh sphere = makeIcosphere(1.3, 2);
  ShellSamplingSettings settings;
  settings.points = 300;
  settings.iterations = 3;
  const PointShell shell = sampleShell(sphere, settings);
  expectAreasSumTo(shell, sphere.area());
  for (double a : shell.areas) EXPECT_EQ(a, shell.areas.front());
  expectAreasSumTo(sampleShell(makeBox(Vec3(0.1, 0.2, 0.3)), settings), 8.0 * (0.02 + 0.06 + 0.03));
}

TEST(PointAreas, BoxShellsSumToTheBoxAreaAndCornersCarryLess) {
  const Vec3 h(0.05, 0.12, 0.3);
  AnalyticShellSettings settings;
  settings.spacing = 0.013;  // non-uniform steps per axis
  const PointShell shell = boxShell(h, settings);
  expectAreasSumTo(shell, 8.0 * (h.x() * h.y() + h.y() * h.z() + h.x() * h.z()));
  // Lattice steps 2h/ceil(2h/spacing): a corner carries a quarter cell of each of its 3 faces, a point inside
  // the face +x a whole cell of it.
  const Vec3 step(0.1 / 8, 0.24 / 19, 0.6 / 47);
  int corners = 0;
  int inside = 0;
  for (std::size_t i = 0; i < shell.size(); ++i) {
    const Vec3& p = shell.positions[i];
    if (p.cwiseAbs() == h) {
      ++corners;
      EXPECT_NEAR(shell.areas[i], 0.25 * (step.y() * step.z() + step.x() * step.z() + step.x() * step.y()), 1e-15);
    } else if (p.x() == h.x() && std::abs(p.y()) < h.y() && std::abs(p.z()) < h.z()) {
      ++inside;
      EXPECT_NEAR(shell.areas[i], step.y() * step.z(), 1e-15);
    }
  }
  EXPECT_EQ(corners, 8);
  EXPECT_EQ(inside, 18 * 46);
  // The 8 corners of a coarse box (2 x 2 x 2 lattice steps): a corner carries 3 quarter cells.
  AnalyticShellSettings coarse;
  coarse.spacing = 1.0;
  const PointShell cube = boxShell(Vec3::Constant(0.5), coarse);
  ASSERT_EQ(cube.size(), 8u);
  for (double a : cube.areas) EXPECT_NEAR(a, 0.75, 1e-15);
}

TEST(PointAreas, SphereAndCapsuleShellsSumToTheirClosedForms) {
  AnalyticShellSettings settings;
  settings.spacing = 0.07;
  expectAreasSumTo(sphereShell(0.9, settings), 4.0 * kPi * 0.81);
  for (int axis = 0; axis < 3; ++axis) {
    expectAreasSumTo(capsuleShell(0.25, 0.6, axis, settings), 2.0 * kPi * 0.25 * 1.2 + 4.0 * kPi * 0.0625);
  }
  expectAreasSumTo(capsuleShell(0.25, 0.0, 1, settings), 4.0 * kPi * 0.0625);  // a sphere-capsule
  settings.maxPoints = 40;  // the cap grows the spacing; the sum stays exact
  expectAreasSumTo(capsuleShell(0.25, 0.6, 2, settings), 2.0 * kPi * 0.25 * 1.2 + 4.0 * kPi * 0.0625);
}

TEST(PointAreas, LoadedShellsGetUniformAreasFromTheirSurface) {
  const TriangleMesh sphere = makeIcosphere(1.0, 1);
  PointShell shell = parseShell("x,y,z,nx,ny,nz\n1,0,0,1,0,0\n0,1,0,0,1,0\n0,0,1,0,0,1\n", "three.csv");
  EXPECT_TRUE(shell.areas.empty());
  EXPECT_FALSE(shell.hasAreas());
  EXPECT_EQ(shell.totalArea(), 0.0);
  assignUniformAreas(shell, sphere.area());
  expectAreasSumTo(shell, sphere.area());
  EXPECT_THROW(assignUniformAreas(shell, 0.0), Error);
  EXPECT_THROW(assignUniformAreas(shell, -1.0), Error);
  EXPECT_THROW(assignUniformAreas(shell, std::nan("")), Error);
  PointShell empty;
  EXPECT_THROW(assignUniformAreas(empty, 1.0), Error);
}

TEST(PointAreas, ValidateRejectsBadAreas) {
  PointShell shell = shellFromVertices(makeBox(Vec3::Constant(1.0)));
  shell.areas.pop_back();
  EXPECT_THROW(shell.validate(), Error);
  shell.areas.push_back(0.0);
  EXPECT_THROW(shell.validate(), Error);
  shell.areas.back() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(shell.validate(), Error);
  shell.areas.back() = 1.0;
  EXPECT_NO_THROW(shell.validate());
  shell.areas.clear();  // unknown areas are allowed
  EXPECT_NO_THROW(shell.validate());
}

}  // namespace
}  // namespace sdfccd
