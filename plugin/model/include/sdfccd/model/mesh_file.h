/// @file
/// @brief loadMeshFile: the model layer's one way to read a mesh file (body models, simulation and haptic scenes,
/// the tool's run folders).
///
/// @details Reading goes through sdfccd::io (assimp) when this build has it; a build without assimp still has the
/// whole model layer (procedural shapes, fields and shells from files) and says so in one line when a mesh file is
/// asked for. The mesh is checked as every mesh is (checkMesh, triangle_mesh.h).
#pragma once

#include <string>

#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd {

/// True when this build reads mesh files (sdfccd::io was built, with assimp).
bool canLoadMeshFiles();

/// Loads and repairs the mesh in `path` (any format sdfccd::io reads). Throws sdfccd::Error (one line naming
/// the file) on a missing or bad file, or when the build has no mesh loader.
TriangleMesh loadMeshFile(const std::string& path);

}  // namespace sdfccd
