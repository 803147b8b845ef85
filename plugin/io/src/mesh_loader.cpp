/// @file
/// @brief loadMesh through assimp: every mesh of the scene, node transforms applied, then repairMesh.
#include "sdfccd/io/mesh_loader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <sys/stat.h>

#include <assimp/Importer.hpp>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "sdfccd/error.h"
#include "sdfccd/output_file.h"

namespace sdfccd {

namespace {

std::string oneLine(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

// Appends the triangles of `node` and its children, with the accumulated transform applied.
void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parentTransform, TriangleMesh& out) {
  const aiMatrix4x4 transform = parentTransform * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    if (!(mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const int base = static_cast<int>(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      out.vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines left by SortByPType
      out.triangles.push_back({base + static_cast<int>(face.mIndices[0]), base + static_cast<int>(face.mIndices[1]),
                               base + static_cast<int>(face.mIndices[2])});
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) collect(scene, *node.mChildren[c], transform, out);
}

}  // namespace

TriangleMesh loadMesh(const std::string& path, MeshRepairReport* outReport, const MeshRepairSettings& repairSettings) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw Error("cannot open mesh '" + path + "': " + std::strerror(errno));
  if (S_ISDIR(info.st_mode)) throw Error("cannot read mesh '" + path + "': it is a directory");
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw Error("cannot open mesh '" + path + "': " + std::strerror(errno));
  }
  if (info.st_size == 0) throw Error("mesh file '" + path + "' is empty");

  Assimp::Importer importer;
  // Keep only positions: normals, UVs, colours and so on are irrelevant to distances.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                                          aiComponent_COLORS | aiComponent_TEXCOORDS |
                                                          aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                                          aiComponent_TEXTURES | aiComponent_LIGHTS |
                                                          aiComponent_CAMERAS | aiComponent_MATERIALS);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // No aiProcess_FixInfacingNormals (a normal-based guess) and no FindDegenerates/FindInvalidData: repairMesh
  // orients by topology and counts what it drops, so the report is honest.
  const unsigned flags =
      aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_RemoveComponent | aiProcess_SortByPType;
  // Validate before any post-processing step runs: a truncated file (e.g. an OFF header promising more faces
  // than it lists) leaves empty faces that trip an assertion (abort) inside assimp's TriangulateProcess.
  const aiScene* scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
  if (scene != nullptr && scene->mRootNode != nullptr) scene = importer.ApplyPostProcessing(flags);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    throw Error("cannot read mesh '" + path + "': " + oneLine(importer.GetErrorString()));
  }
  TriangleMesh mesh;
  collect(*scene, *scene->mRootNode, aiMatrix4x4(), mesh);
  if (mesh.triangles.empty()) throw Error("mesh file '" + path + "' holds no triangles");
  try {
    const MeshRepairReport report = repairMesh(mesh, repairSettings);
    if (outReport != nullptr) *outReport = report;
  } catch (const Error& e) {
    throw Error("mesh '" + path + "': " + e.what());
  }
  return mesh;
}

void saveMeshOff(const std::string& path, const TriangleMesh& mesh) {
  std::ostringstream s;
  s.precision(17);
  s << "OFF\n" << mesh.vertices.size() << ' ' << mesh.triangles.size() << " 0\n";
  for (const Vec3& v : mesh.vertices) s << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const auto& t : mesh.triangles) s << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  writeOutputFile(path, s.str());
}

}  // namespace sdfccd
