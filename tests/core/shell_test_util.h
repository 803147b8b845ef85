/// @file
/// @brief Test helpers for shells and trees: mesh checks, brute-force point-to-mesh distance, a small OFF
/// reader (sdf_test_meshes.h: the core suite must not link assimp), random shells and poses.
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
#include "core/sdf_test_meshes.h"
#include "sdfccd/mesh/triangle_mesh.h"
#include "sdfccd/shell/point_shell.h"

namespace sdfccd::test {

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
