/// @file
/// @brief loadMesh through assimp: OBJ, OFF, PLY and STL written by the test, repairs, and bad files.
#include "sdfccd/io/mesh_loader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

std::string tempFile(const std::string& name, const std::string& contents) {
  const std::string path = ::testing::TempDir() + "sdfccd-loader-" + std::to_string(::getpid()) + "-" + name;
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

// The unit cube [0,1]^3: corners (bit 0 = x, bit 1 = y, bit 2 = z) and outward quads.
const double kCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
const int kQuads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};

std::string cubeObj() {
  std::string s = "# cube with quads\no cube\n";
  for (const auto& c : kCorner)
    s += "v " + std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) + "\n";
  for (const auto& q : kQuads)
    s += "f " + std::to_string(q[0] + 1) + " " + std::to_string(q[1] + 1) + " " + std::to_string(q[2] + 1) + " " +
         std::to_string(q[3] + 1) + "\n";
  return s;
}

// The cube's corners, one per line, then its quads as "4 a b c d" with 0-based indices: the body of OFF and of
// an ASCII PLY alike.
std::string cubeBody() {
  std::string s;
  for (const auto& c : kCorner)
    s += std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) + "\n";
  for (const auto& q : kQuads)
    s += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
         std::to_string(q[3]) + "\n";
  return s;
}

std::string cubeOff() {
  return "OFF\n8 6 0\n" + cubeBody();
}

std::string cubePly() {
  return "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 6\nproperty list uchar int vertex_indices\nend_header\n" +
         cubeBody();
}

// STL stores every triangle with its own three vertices.
std::string cubeStl() {
  std::string s = "solid cube\n";
  for (const auto& q : kQuads) {
    for (const auto& t : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
      s += " facet normal 0 0 0\n  outer loop\n";
      for (int c : t) {
        s += "   vertex " + std::to_string(kCorner[c][0]) + " " + std::to_string(kCorner[c][1]) + " " +
             std::to_string(kCorner[c][2]) + "\n";
      }
      s += "  endloop\n endfacet\n";
    }
  }
  return s + "endsolid cube\n";
}

void expectUnitCube(const TriangleMesh& mesh, const MeshRepairReport& report) {
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  EXPECT_TRUE(report.closed);
  EXPECT_EQ(report.components, 1);
  EXPECT_NEAR(mesh.signedVolume(), 1.0, 1e-6);
  EXPECT_NEAR(mesh.area(), 6.0, 1e-6);
}

TEST(MeshLoader, LoadsObjOffPlyAndStl) {
  for (const auto& [name, contents] : {std::pair<std::string, std::string>{"cube.obj", cubeObj()},
                                       {"cube.off", cubeOff()},
                                       {"cube.ply", cubePly()},
                                       {"cube.stl", cubeStl()}}) {
    SCOPED_TRACE(name);
    const std::string path = tempFile(name, contents);
    MeshRepairReport report;
    const TriangleMesh mesh = loadMesh(path, &report);
    expectUnitCube(mesh, report);
    std::remove(path.c_str());
  }
}

TEST(MeshLoader, MergesObjectsAndAppliesRepairs) {
  // Two objects: the cube, and a copy of the cube inside out and shifted (a second closed component),
  // plus a degenerate face (a repeated corner).
  std::string s = cubeObj();
  s += "o second\n";
  for (const auto& c : kCorner)
    s += "v " + std::to_string(c[0] + 3) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) + "\n";
  for (const auto& q : kQuads)
    s += "f " + std::to_string(q[3] + 9) + " " + std::to_string(q[2] + 9) + " " + std::to_string(q[1] + 9) + " " +
         std::to_string(q[0] + 9) + "\n";
  s += "f 1 2 2\n";
  const std::string path = tempFile("two.obj", s);
  MeshRepairReport report;
  const TriangleMesh mesh = loadMesh(path, &report);
  EXPECT_EQ(report.components, 2);
  EXPECT_EQ(report.reorientedFaces, 12);
  EXPECT_TRUE(report.closed);
  EXPECT_EQ(mesh.triangles.size(), 24u);
  EXPECT_NEAR(mesh.signedVolume(), 2.0, 1e-6);
  std::remove(path.c_str());
}

TEST(MeshLoader, ReportsHolesOfTheDragon) {
  MeshRepairReport report;
  const TriangleMesh mesh = loadMesh(std::string(SDFCCD_ASSETS_DIR) + "/meshes/dragon.off", &report);
  EXPECT_FALSE(report.closed);
  EXPECT_EQ(report.boundaryEdges, 6);
  EXPECT_GT(mesh.triangles.size(), 19000u);
}

TEST(MeshLoader, BadFilesGiveOneLineErrorsNamingTheFile) {
  const std::string empty = tempFile("empty.obj", "");
  const std::string garbage = tempFile("garbage.stl", std::string("\x01\x02 this is not a mesh \xff\xfe", 24));
  const std::string points = tempFile("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  const std::string nan = tempFile("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  // The header promises 4 faces, the file lists 2: an error, never an abort inside assimp's triangulation step.
  const std::string truncated = tempFile("truncated.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n");
  for (const std::string& path :
       {std::string("/nonexistent/mesh.obj"), empty, garbage, points, nan, truncated, ::testing::TempDir()}) {
    SCOPED_TRACE(path);
    try {
      loadMesh(path);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      EXPECT_NE(message.find(path), std::string::npos) << message;
    }
  }
  for (const auto& p : {empty, garbage, points, nan, truncated}) std::remove(p.c_str());
}

// Assimp's OFF reader clamps an index past the vertex count to the last vertex; the loader refuses the file,
// naming the file, line and face.
TEST(MeshLoader, OffFaceIndexPastVertexCountIsRefused) {
  const std::string past =
      tempFile("past.off", "OFF\n# a comment\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 9\n");
  const std::string negative = tempFile("negative.off", "OFF 4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 -1 2\n");
  for (const std::string& path : {past, negative}) {
    SCOPED_TRACE(path);
    try {
      loadMesh(path);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      EXPECT_NE(message.find(path), std::string::npos) << message;
      EXPECT_NE(message.find("not in 0..3"), std::string::npos) << message;
    }
  }
  try {
    loadMesh(past);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("line 9, face 1"), std::string::npos) << e.what();
  }
  for (const auto& p : {past, negative}) std::remove(p.c_str());
}

TEST(MeshLoader, SavedOffReadsBack) {
  MeshRepairReport report;
  const std::string in = tempFile("in.off", cubeOff());
  const TriangleMesh mesh = loadMesh(in, &report);
  const std::string out = ::testing::TempDir() + "sdfccd-loader-out-" + std::to_string(::getpid()) + ".off";
  saveMeshOff(out, mesh);
  const TriangleMesh again = loadMesh(out, &report);
  expectUnitCube(again, report);
  std::remove(in.c_str());
  std::remove(out.c_str());
}

}  // namespace
}  // namespace sdfccd
