/// @file
/// @brief MeshPseudonormals: angle-weighted pseudonormals of faces, edges and vertices. Internal header.
///
/// @details Baerentzen & Aanaes, "Signed distance computation using the angle weighted pseudonormal" (2005):
/// on a closed, consistently oriented mesh, the sign of (p - q) . n, with q the closest point to p and n the
/// pseudonormal of the feature q lies on (face normal; sum of the two face normals for an edge; angle-weighted
/// sum for a vertex), is negative exactly when p is inside.
#pragma once

#include <array>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"
#include "triangle_distance.h"

namespace sdfccd::detail {

class MeshPseudonormals {
 public:
  explicit MeshPseudonormals(const TriangleMesh& mesh);

  /// The pseudonormal of `feature` of mesh triangle `triangle` (not normalized; only its direction matters).
  const Vec3& normal(int triangle, TriangleFeature feature) const {
    switch (feature) {
      case TriangleFeature::Face:
        return m_face[triangle];
      case TriangleFeature::EdgeAB:
        return m_edge[triangle][0];
      case TriangleFeature::EdgeBC:
        return m_edge[triangle][1];
      case TriangleFeature::EdgeCA:
        return m_edge[triangle][2];
      case TriangleFeature::VertexA:
        return m_vertex[m_triangles[triangle][0]];
      case TriangleFeature::VertexB:
        return m_vertex[m_triangles[triangle][1]];
      case TriangleFeature::VertexC:
        return m_vertex[m_triangles[triangle][2]];
    }
    return m_face[triangle];
  }

  std::size_t memoryBytes() const {
    return m_face.capacity() * sizeof(Vec3) + m_edge.capacity() * sizeof(m_edge[0]) +
           m_vertex.capacity() * sizeof(Vec3);
  }

 private:
  const std::vector<std::array<int, 3>>& m_triangles;
  std::vector<Vec3> m_face;
  std::vector<std::array<Vec3, 3>> m_edge;
  std::vector<Vec3> m_vertex;
};

}  // namespace sdfccd::detail
