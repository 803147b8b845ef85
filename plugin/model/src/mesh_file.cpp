/// @file
/// @brief loadMeshFile through sdfccd::io, or a one-line error in builds without assimp.
#include "sdfccd/model/mesh_file.h"

#include "sdfccd/error.h"

#if SDFCCD_MODEL_HAS_IO
#include "sdfccd/io/mesh_loader.h"
#endif

namespace sdfccd {

bool canLoadMeshFiles() {
  return SDFCCD_MODEL_HAS_IO != 0;
}

TriangleMesh loadMeshFile(const std::string& path) {
#if SDFCCD_MODEL_HAS_IO
  TriangleMesh mesh = loadMesh(path);
  checkMesh(mesh, "mesh '" + path + "'");
  return mesh;
#else
  throw Error("cannot read mesh '" + path + "': this build of sdfccd has no mesh loader (assimp was not found)");
#endif
}

}  // namespace sdfccd
