/// @file
/// @brief loadMesh: any mesh format assimp reads (OBJ, OFF, PLY, STL, glTF, ...) into a repaired TriangleMesh.
///
/// @details Every mesh of the scene is merged, with its node transforms applied; polygons are triangulated.
/// The result then goes through repairMesh (merge duplicate vertices, drop degenerate and duplicate faces,
/// orient consistently and outward); the report says what changed. assimp's own FixInfacingNormals step is
/// not used: it guesses from normals and can flip correct open meshes; repairMesh orients by topology.
#pragma once

#include <string>

#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd {

/// Loads and repairs the mesh in `path`. Throws sdfccd::Error (one line naming the file) if the file is
/// missing, unreadable, of an unknown format, holds no triangles, or has non-finite coordinates.
TriangleMesh loadMesh(const std::string& path, MeshRepairReport* outReport = nullptr,
                      const MeshRepairSettings& repairSettings = {});

/// Writes `mesh` as ASCII OFF, atomically. Throws sdfccd::Error on failure.
void saveMeshOff(const std::string& path, const TriangleMesh& mesh);

}  // namespace sdfccd
