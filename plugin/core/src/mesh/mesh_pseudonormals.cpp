/// @file
/// @brief MeshPseudonormals: face, edge (by sorting half-edges) and angle-weighted vertex normals.
#include "mesh_pseudonormals.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace sdfccd::detail {

MeshPseudonormals::MeshPseudonormals(const TriangleMesh& mesh) : m_triangles(mesh.triangles) {
  const std::size_t n = mesh.triangles.size();
  m_face.resize(n);
  m_edge.resize(n);
  m_vertex.assign(mesh.vertices.size(), Vec3::Zero());
  for (std::size_t t = 0; t < n; ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 normal =
        (mesh.vertices[tri[1]] - mesh.vertices[tri[0]]).cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]]);
    const double length = normal.norm();
    m_face[t] = length > 0.0 ? Vec3(normal / length) : Vec3::Zero();
    for (int corner = 0; corner < 3; ++corner) {
      const Vec3& v = mesh.vertices[tri[corner]];
      const Vec3 e1 = mesh.vertices[tri[(corner + 1) % 3]] - v;
      const Vec3 e2 = mesh.vertices[tri[(corner + 2) % 3]] - v;
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      m_vertex[tri[corner]] += angle * m_face[t];
    }
  }
  // Edge normals: the sum of the unit normals of the faces sharing the edge (each face's angle at an edge
  // is pi, so the weights cancel). Half-edges sorted by their undirected key group those faces.
  struct HalfEdge {
    std::uint64_t key;
    std::uint32_t face;
    std::uint8_t slot;
  };
  std::vector<HalfEdge> edges;
  edges.reserve(3 * n);
  for (std::size_t t = 0; t < n; ++t) {
    for (int e = 0; e < 3; ++e) {
      const auto a = static_cast<std::uint64_t>(mesh.triangles[t][e]);
      const auto b = static_cast<std::uint64_t>(mesh.triangles[t][(e + 1) % 3]);
      edges.push_back(
          {std::min(a, b) << 32 | std::max(a, b), static_cast<std::uint32_t>(t), static_cast<std::uint8_t>(e)});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) { return x.key < y.key; });
  for (std::size_t s = 0; s < edges.size();) {
    std::size_t e = s + 1;
    while (e < edges.size() && edges[e].key == edges[s].key) ++e;
    Vec3 sum = Vec3::Zero();
    for (std::size_t m = s; m < e; ++m) sum += m_face[edges[m].face];
    for (std::size_t m = s; m < e; ++m) m_edge[edges[m].face][edges[m].slot] = sum;
    s = e;
  }
}

}  // namespace sdfccd::detail
