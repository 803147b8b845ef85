/// @file
/// @brief Closed meshes with known shapes for the render tests: an icosphere and an axis-aligned box.
#pragma once

#include <map>
#include <memory>
#include <utility>

#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd::render::test {

/// A unit-radius icosphere: an icosahedron split `subdivisions` times, vertices pushed onto the sphere.
inline std::shared_ptr<TriangleMesh> makeIcosphere(int subdivisions) {
  auto mesh = std::make_shared<TriangleMesh>();
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const double base[12][3] = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                              {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (const auto& v : base) mesh->vertices.push_back(Vec3(v[0], v[1], v[2]).normalized());
  mesh->triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                     {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                     {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      mesh->vertices.push_back((mesh->vertices[a] + mesh->vertices[b]).normalized());
      const int index = static_cast<int>(mesh->vertices.size()) - 1;
      midpoints[key] = index;
      return index;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& tri : mesh->triangles) {
      const int ab = midpoint(tri[0], tri[1]);
      const int bc = midpoint(tri[1], tri[2]);
      const int ca = midpoint(tri[2], tri[0]);
      finer.push_back({tri[0], ab, ca});
      finer.push_back({tri[1], bc, ab});
      finer.push_back({tri[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    mesh->triangles = std::move(finer);
  }
  return mesh;
}

/// The box [-h, h] (component-wise), 12 outward triangles.
inline std::shared_ptr<TriangleMesh> makeBox(const Vec3& halfSize) {
  auto mesh = std::make_shared<TriangleMesh>();
  for (int i = 0; i < 8; ++i) {
    mesh->vertices.push_back(Vec3((i & 1) ? halfSize.x() : -halfSize.x(), (i & 2) ? halfSize.y() : -halfSize.y(),
                                  (i & 4) ? halfSize.z() : -halfSize.z()));
  }
  mesh->triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                     {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

}  // namespace sdfccd::render::test
