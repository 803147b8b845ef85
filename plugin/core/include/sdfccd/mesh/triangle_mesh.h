/// @file
/// @brief An indexed triangle mesh in double precision, and its repair (merge, drop degenerates, orient).
///
/// @details Meshes reach the core from any loader (sdfccd::io uses assimp) as a soup of vertices and index
/// triples. repairMesh() makes it fit for distance computation: duplicate vertices merged, degenerate and
/// duplicate faces dropped, faces oriented consistently per connected component and outward (positive volume
/// on closed components). The report says what was changed, and whether the result is closed (watertight).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sdfccd/math_types.h"

namespace sdfccd {

/// Vertices and counter-clockwise (outward) triangles. Indices are 0-based.
struct TriangleMesh {
  std::vector<Vec3> vertices;                 ///< positions, in the mesh's own frame (model units)
  std::vector<std::array<int, 3>> triangles;  ///< vertex indices, counter-clockwise seen from outside

  /// The axis-aligned box of all vertices (empty box for an empty mesh).
  Box3 bounds() const;
  /// Signed volume by the divergence theorem: positive for a closed, outward-oriented mesh. (model units^3)
  double signedVolume() const;
  /// Total surface area (model units^2).
  double area() const;
};

/// What repairMesh changed and found.
struct MeshRepairReport {
  int mergedVertices = 0;        ///< vertices merged into an earlier one at the same position
  int droppedDegenerate = 0;     ///< faces with repeated indices or (near) zero area
  int droppedDuplicates = 0;     ///< faces using the same three vertices as an earlier face
  int reorientedFaces = 0;       ///< faces flipped to agree with their neighbours / to point outward
  int unreferencedVertices = 0;  ///< vertices used by no face, removed
  int boundaryEdges = 0;         ///< edges used by one face only (holes, open boundaries)
  int nonManifoldEdges = 0;      ///< edges used by more than two faces
  int components = 0;            ///< connected components (by shared edges)
  bool closed = false;           ///< no boundary and no non-manifold edges: sign by pseudonormals is exact

  /// One line describing the repairs, e.g. "merged 12 vertices, dropped 3 degenerate faces; closed".
  std::string summary() const;
};

/// Settings of repairMesh.
struct MeshRepairSettings {
  double mergeTolerance = 0.0;  ///< vertices closer than this merge (model units); 0 merges exact duplicates
  bool orient = true;           ///< make orientation consistent and outward
};

/// The one validity check every consumer of a mesh runs first (repair, SDF build, mass properties, shells,
/// mesh files): throws sdfccd::Error "<who>: ..." (one line) if `mesh` has no vertex or no triangle, a
/// non-finite vertex, or a triangle index out of range.
void checkMesh(const TriangleMesh& mesh, const std::string& who);

/// Repairs `ioMesh` in place. Throws sdfccd::Error if the mesh is empty or has non-finite coordinates, or
/// if nothing is left after dropping degenerate faces.
MeshRepairReport repairMesh(TriangleMesh& ioMesh, const MeshRepairSettings& settings = {});

}  // namespace sdfccd
