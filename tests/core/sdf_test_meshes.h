/// @file
/// @brief Meshes and reference distances for the SDF tests, written independently of the builder.
///
/// @details The reference point-triangle distance here projects onto the plane and, when the projection
/// falls outside, takes the nearest of the three edge segments: a different method from the builder's
/// Voronoi-region walk, so the two check each other.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "sdfccd/error.h"
#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd::test {

inline double segmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 e = b - a;
  const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * e)).norm();
}

inline double triangleDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const Vec3 foot = p - n * ((p - a).dot(n) / n.squaredNorm());
  const bool inside = (b - a).cross(foot - a).dot(n) >= 0.0 && (c - b).cross(foot - b).dot(n) >= 0.0 &&
                      (a - c).cross(foot - c).dot(n) >= 0.0;
  if (inside) return (p - foot).norm();
  return std::min({segmentDistance(p, a, b), segmentDistance(p, b, c), segmentDistance(p, c, a)});
}

/// Unsigned distance from p to the whole triangle set, by brute force.
inline double bruteForceDistance(const TriangleMesh& mesh, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles) {
    best = std::min(best, triangleDistance(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
  }
  return best;
}

/// Axis-aligned box [-h, h], 12 outward triangles.
inline TriangleMesh boxMesh(const Vec3& h) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k)
    m.vertices.emplace_back((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z());
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

/// Exact signed distance to the box [-h, h].
inline double boxSignedDistance(const Vec3& p, const Vec3& h) {
  const Vec3 q = p.cwiseAbs() - h;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// A tetrahedron with outward faces.
inline TriangleMesh tetrahedronMesh() {
  TriangleMesh m;
  m.vertices = {Vec3(0.1, -0.2, 0.05), Vec3(1.0, 0.1, -0.1), Vec3(0.2, 0.9, 0.15), Vec3(0.3, 0.2, 0.8)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  if (m.signedVolume() < 0.0) {
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  }
  return m;
}

/// Icosphere of radius r: an icosahedron subdivided `levels` times, vertices on the sphere.
inline TriangleMesh icosphereMesh(double r, int levels) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh m;
  m.vertices = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  m.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::vector<std::array<int, 3>> next;
    std::vector<std::pair<std::pair<int, int>, int>> midpoints;
    auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      for (const auto& [k, v] : midpoints)
        if (k == key) return v;
      m.vertices.push_back(0.5 * (m.vertices[a] + m.vertices[b]));
      midpoints.push_back({key, static_cast<int>(m.vertices.size()) - 1});
      return static_cast<int>(m.vertices.size()) - 1;
    };
    for (const auto& t : m.triangles) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    m.triangles = next;
  }
  for (Vec3& v : m.vertices) v = r * v.normalized();
  return m;
}

/// Reads a plain OFF file (the test suites of the core cannot use assimp): triangles, and convex polygons
/// fanned from their first vertex. No repair; a bad header, face or index throws.
inline TriangleMesh readOff(const std::string& path) {
  std::ifstream in(path);
  std::string magic;
  in >> magic;
  if (magic != "OFF") throw Error("not OFF: " + path);
  std::size_t nv = 0, nf = 0, ne = 0;
  in >> nv >> nf >> ne;
  TriangleMesh m;
  m.vertices.resize(nv);
  for (auto& v : m.vertices) in >> v.x() >> v.y() >> v.z();
  for (std::size_t f = 0; f < nf; ++f) {
    int k = 0;
    in >> k;
    if (k < 3) throw Error("face with fewer than 3 vertices in " + path);
    std::vector<int> idx(static_cast<std::size_t>(k));
    for (int& i : idx) {
      in >> i;
      if (i < 0 || static_cast<std::size_t>(i) >= nv) throw Error("vertex index out of range in " + path);
    }
    for (int j = 1; j + 1 < k; ++j) m.triangles.push_back({idx[0], idx[j], idx[j + 1]});
  }
  if (!in) throw Error("truncated OFF: " + path);
  return m;
}

}  // namespace sdfccd::test
