/// @file
/// @brief Test helpers for shells and trees: mesh checks, brute-force point-to-mesh distance, a small OFF
/// reader (the core suite must not link assimp), random shells and poses.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <utility>

#include "../../demos/bench/random_pose.h"
#include "sdfccd/mesh/triangle_mesh.h"
#include "sdfccd/shell/point_shell.h"

namespace sdfccd::test {

/// Distance from p to segment ab.
inline double segmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (a + t * d - p).norm();
}

/// Distance from p to triangle abc: the plane distance when the projection falls inside, else the nearest edge.
inline double triangleDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  if (n2 > 0.0) {
    const Vec3 q = p - (p - a).dot(n) / n2 * n;
    const bool in =
        (b - a).cross(q - a).dot(n) >= 0.0 && (c - b).cross(q - b).dot(n) >= 0.0 && (a - c).cross(q - c).dot(n) >= 0.0;
    if (in) return (p - q).norm();
  }
  return std::min({segmentDistance(p, a, b), segmentDistance(p, b, c), segmentDistance(p, c, a)});
}

/// Distance from p to the mesh (brute force), and the triangle reached.
inline double meshDistance(const TriangleMesh& mesh, const Vec3& p, int* outTriangle = nullptr) {
  double best = std::numeric_limits<double>::infinity();
  for (int f = 0; f < static_cast<int>(mesh.triangles.size()); ++f) {
    const auto& t = mesh.triangles[f];
    const double d = triangleDistance(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    if (d < best) {
      best = d;
      if (outTriangle) *outTriangle = f;
    }
  }
  return best;
}

/// Closed and consistently oriented: every directed edge appears once and its reverse once.
inline bool closedAndOriented(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) ++directed[{t[c], t[(c + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end() || reverse->second != 1) return false;
  }
  return true;
}

inline double volume(const TriangleMesh& mesh) {
  double sum = 0.0;
  for (const auto& t : mesh.triangles) {
    sum += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  }
  return sum / 6.0;
}

inline double area(const TriangleMesh& mesh) {
  double sum = 0.0;
  for (const auto& t : mesh.triangles) {
    sum += 0.5 * (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).norm();
  }
  return sum;
}

/// A minimal OFF reader for the test assets (triangles and convex polygons fanned). No repair.
inline TriangleMesh readOff(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::string magic;
  in >> magic;
  int nv = 0, nf = 0, ne = 0;
  in >> nv >> nf >> ne;
  TriangleMesh mesh;
  mesh.vertices.resize(nv);
  for (auto& v : mesh.vertices) in >> v.x() >> v.y() >> v.z();
  for (int f = 0; f < nf; ++f) {
    int k = 0;
    in >> k;
    std::vector<int> idx(k);
    for (auto& i : idx) in >> i;
    for (int j = 1; j + 1 < k; ++j) mesh.triangles.push_back({idx[0], idx[j], idx[j + 1]});
  }
  EXPECT_FALSE(in.fail()) << path;
  return mesh;
}

/// Random points in a ball of `radius` with random unit normals.
inline PointShell randomShell(int count, double radius, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PointShell shell;
  for (int n = 0; n < count; ++n) {
    Vec3 d(g(rng), g(rng), g(rng));
    shell.positions.push_back(d.normalized() * radius * std::cbrt(u(rng)));
    shell.normals.push_back(Vec3(g(rng), g(rng), g(rng)).normalized());
  }
  return shell;
}

/// A random rigid transform: rotation uniform, translation uniform in `box` (the bench's Table 3 protocol).
using bench::randomPose;

}  // namespace sdfccd::test
