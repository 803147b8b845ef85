/// @file
/// @brief Point shells: vertex normals, repulsion sampling (on the mesh, unit outward normals, evenly spread,
/// deterministic), open meshes, shell files (round trip; bad files rejected with one clear line).
#include "sdfccd/shell/point_shell.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "core/shell_test_util.h"
#include "sdfccd/error.h"
#include "sdfccd/mesh/procedural_meshes.h"

namespace sdfccd {
namespace {

namespace fs = std::filesystem;

// Smallest distance from each point to another, the minimum over all points (brute force).
double minNeighbourDistance(const PointShell& shell) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < shell.size(); ++i) {
    for (std::size_t j = i + 1; j < shell.size(); ++j) {
      best = std::min(best, (shell.positions[i] - shell.positions[j]).norm());
    }
  }
  return best;
}

TEST(PointShell, VertexNormalsOfASphereAreRadial) {
  const TriangleMesh sphere = makeIcosphere(1.5, 2);
  const PointShell shell = shellFromVertices(sphere);
  ASSERT_EQ(shell.size(), sphere.vertices.size());
  shell.validate();
  for (std::size_t n = 0; n < shell.size(); ++n) {
    EXPECT_NEAR(shell.normals[n].norm(), 1.0, 1e-12);
    EXPECT_GT(shell.normals[n].dot(shell.positions[n].normalized()), 0.995);
  }
}

TEST(PointShell, VertexNormalsAreAreaWeighted) {
  // Vertex 0 is shared by a big triangle facing +z and a small one facing -x: the normal leans to +z by
  // the area ratio.
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, -1, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 1, 2}, {0, 3, 4}};
  const PointShell shell = shellFromVertices(mesh);
  ASSERT_EQ(shell.size(), 5u);
  const Vec3 expected = Vec3(-0.5, 0.0, 8.0).normalized();  // areas 8 (+z) and 0.5 (-x)
  EXPECT_TRUE(shell.normals[0].isApprox(expected, 1e-12));
}

TEST(PointShell, VerticesOfNoFaceAreLeftOut) {
  TriangleMesh mesh = makeBox(Vec3::Ones());
  mesh.vertices.emplace_back(9.0, 9.0, 9.0);  // unreferenced
  EXPECT_EQ(shellFromVertices(mesh).size(), 8u);
  EXPECT_THROW(shellFromVertices(TriangleMesh{}), Error);
}

TEST(PointShell, SampledPointsLieOnTheSphereWithRadialNormals) {
  const TriangleMesh sphere = makeIcosphere(1.0, 3);
  ShellSamplingSettings settings;
  settings.points = 400;
  const PointShell shell = sampleShell(sphere, settings);
  ASSERT_EQ(shell.size(), 400u);
  shell.validate();
  for (std::size_t n = 0; n < shell.size(); ++n) {
    int face = -1;
    EXPECT_LT(test::meshDistance(sphere, shell.positions[n], &face), 1e-12);
    EXPECT_NEAR(shell.normals[n].norm(), 1.0, 1e-12);
    EXPECT_GT(shell.normals[n].dot(shell.positions[n].normalized()), 0.98);
  }
}

TEST(PointShell, RepulsionSpreadsPointsEvenly) {
  const TriangleMesh sphere = makeIcosphere(1.0, 3);
  ShellSamplingSettings random;
  random.points = 300;
  random.iterations = 0;
  ShellSamplingSettings relaxed = random;
  relaxed.iterations = 30;
  const double before = minNeighbourDistance(sampleShell(sphere, random));
  const double after = minNeighbourDistance(sampleShell(sphere, relaxed));
  // Even spacing on a unit sphere with 300 points is about sqrt(4 pi / 300) ~ 0.2; random samples cluster.
  EXPECT_GT(after, 3.0 * before);
  EXPECT_GT(after, 0.08);
}

TEST(PointShell, SamplingIsDeterministicAndIndependentOfThreads) {
  const TriangleMesh bowl = makeLathedBowl();
  ShellSamplingSettings settings;
  settings.points = 500;
  settings.iterations = 5;
  const PointShell a = sampleShell(bowl, settings);
  settings.threads = 2;
  const PointShell b = sampleShell(bowl, settings);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t n = 0; n < a.size(); ++n) {
    EXPECT_EQ(a.positions[n], b.positions[n]);
    EXPECT_EQ(a.normals[n], b.normals[n]);
  }
  settings.seed = 99;
  EXPECT_NE(sampleShell(bowl, settings).positions[0], a.positions[0]);
}

TEST(PointShell, BowlSamplesAreOnTheMeshAndOutward) {
  const TriangleMesh bowl = makeLathedBowl();
  ShellSamplingSettings settings;
  settings.points = 300;
  const PointShell shell = sampleShell(bowl, settings);
  for (std::size_t n = 0; n < shell.size(); ++n) {
    int face = -1;
    EXPECT_LT(test::meshDistance(bowl, shell.positions[n], &face), 1e-12);
    // Outward: a small step along the normal leaves the (closed) solid, checked by the face's orientation.
    const auto& t = bowl.triangles[face];
    const Vec3 faceNormal =
        (bowl.vertices[t[1]] - bowl.vertices[t[0]]).cross(bowl.vertices[t[2]] - bowl.vertices[t[0]]).normalized();
    EXPECT_GT(shell.normals[n].dot(faceNormal), 0.999);
  }
}

TEST(PointShell, OpenMeshesGiveShellsOnTheSurface) {
  // A box without its top: open, with a boundary loop.
  TriangleMesh open = makeBox(Vec3(1.0, 0.5, 1.0));
  std::vector<std::array<int, 3>> kept;
  for (const auto& t : open.triangles) {
    const bool top = open.vertices[t[0]].y() > 0 && open.vertices[t[1]].y() > 0 && open.vertices[t[2]].y() > 0;
    if (!top) kept.push_back(t);
  }
  open.triangles = kept;
  ASSERT_EQ(open.triangles.size(), 10u);
  EXPECT_FALSE(test::closedAndOriented(open));
  const PointShell vertices = shellFromVertices(open);
  EXPECT_EQ(vertices.size(), 8u);
  vertices.validate();
  ShellSamplingSettings settings;
  settings.points = 200;
  const PointShell sampled = sampleShell(open, settings);
  sampled.validate();
  for (const auto& p : sampled.positions) {
    EXPECT_LT(test::meshDistance(open, p), 1e-12);
    EXPECT_LT(p.y(), 0.5 + 1e-12);
  }
}

TEST(PointShell, SamplingRejectsBadInput) {
  ShellSamplingSettings settings;
  EXPECT_THROW(sampleShell(TriangleMesh{}, settings), Error);
  TriangleMesh flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.triangles = {{0, 1, 2}};
  EXPECT_THROW(sampleShell(flat, settings), Error);
  settings.points = 0;
  EXPECT_THROW(sampleShell(makeBox(Vec3::Ones()), settings), Error);
  TriangleMesh nan = makeBox(Vec3::Ones());
  nan.vertices[0].x() = std::nan("");
  EXPECT_THROW(sampleShell(nan, ShellSamplingSettings{}), Error);
}

class ShellFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir = fs::temp_directory_path() / ("sdfccd_shell_test_" + std::to_string(::getpid()));
    fs::create_directories(m_dir);
  }
  void TearDown() override { fs::remove_all(m_dir); }
  std::string path(const std::string& name) const { return (m_dir / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  // The message of the Error thrown by loadShell, or "" if none.
  static std::string loadError(const std::string& file) {
    try {
      loadShell(file);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
  fs::path m_dir;
};

TEST_F(ShellFiles, PlyAndCsvRoundTripExactly) {
  ShellSamplingSettings settings;
  settings.points = 123;
  settings.iterations = 3;
  const PointShell shell = sampleShell(makeIcosphere(0.7, 2), settings);
  for (const char* name : {"shell.ply", "shell.csv", "SHELL.PLY"}) {
    saveShell(shell, path(name));
    const PointShell back = loadShell(path(name));
    ASSERT_EQ(back.size(), shell.size()) << name;
    for (std::size_t n = 0; n < shell.size(); ++n) {
      EXPECT_EQ(back.positions[n], shell.positions[n]);
      EXPECT_NEAR((back.normals[n] - shell.normals[n]).norm(), 0.0, 1e-15);
    }
  }
  EXPECT_THROW(saveShell(shell, path("shell.xyz")), Error);
  EXPECT_FALSE(fs::exists(path("shell.xyz")));
}

TEST_F(ShellFiles, ForeignPlyWithExtraPropertiesAndFacesLoads) {
  const std::string file = write("foreign.ply",
                                 "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 2\n"
                                 "property float x\nproperty float y\nproperty float z\nproperty float nx\n"
                                 "property float ny\nproperty float nz\nproperty uchar red\n"
                                 "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                 "0 0 0 0 0 2 255\n1 2 3 1 0 0 0\n3 0 1 1\n");
  const PointShell shell = loadShell(file);
  ASSERT_EQ(shell.size(), 2u);
  EXPECT_EQ(shell.positions[1], Vec3(1, 2, 3));
  EXPECT_EQ(shell.normals[0], Vec3(0, 0, 1));  // normalized
}

TEST_F(ShellFiles, BadFilesAreRejectedWithOneClearLine) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
      "property double z\nproperty double nx\nproperty double ny\nproperty double nz\n"
      "end_header\n";
  struct Case {
    std::string name;
    std::string text;
    std::string expect;  // part of the message
  };
  const std::vector<Case> cases = {
      {"truncated.ply", header + "0 0 0 0 0 1\n", "truncated"},
      {"nan.ply", header + "0 0 0 0 0 1\nnan 0 0 0 0 1\n", "non-finite"},
      {"zero.ply", header + "0 0 0 0 0 1\n1 1 1 0 0 0\n", "zero-length normal"},
      {"short.ply", header + "0 0 0 0 0 1\n1 1 1 0 1\n", "expected 6 values"},
      {"word.ply", header + "0 0 0 0 0 1\n1 x 1 0 1 0\n", "not a number"},
      {"extra.ply", header + "0 0 0 0 0 1\n1 1 1 0 1 0\n2 2 2 0 1 0\n", "more points"},
      {"binary.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1\nend_header\n", "ascii"},
      {"nohead.ply", "ply\nformat ascii 1.0\nelement vertex 1\n", "end_header"},
      {"nonormal.ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n0 0 0\n",
       "'nx'"},
      {"notply.ply", "hello\n", "not a PLY"},
      {"empty.ply", "", "not a PLY"},
      {"zero.csv", "x,y,z,nx,ny,nz\n", "no points"},
      {"header.csv", "x,y,z\n1,2,3\n", "header"},
      {"empty.csv", "", "empty"},
      {"columns.csv", "x,y,z,nx,ny,nz\n1,2,3,0,0,1,7\n", "expected 6 values"},
      {"inf.csv", "x,y,z,nx,ny,nz\n1,2,inf,0,0,1\n", "non-finite"},
      {"zeron.csv", "x,y,z,nx,ny,nz\n1,2,3,0,0,0\n", "zero-length normal"},
  };
  for (const auto& c : cases) {
    const std::string message = loadError(write(c.name, c.text));
    EXPECT_NE(message.find(c.expect), std::string::npos) << c.name << ": '" << message << "'";
    EXPECT_NE(message.find(c.name), std::string::npos) << c.name << ": the message names the file";
    EXPECT_EQ(message.find('\n'), std::string::npos) << c.name;
  }
  EXPECT_NE(loadError(path("missing.ply")).find("cannot open"), std::string::npos);
  EXPECT_NE(loadError(path("shell.txt")).find("unknown shell format"), std::string::npos);
}

}  // namespace
}  // namespace sdfccd
