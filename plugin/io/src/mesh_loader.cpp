/// @file
/// @brief loadMesh through assimp: every mesh of the scene, node transforms applied, then repairMesh.
#include "sdfccd/io/mesh_loader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <sys/stat.h>

#include <assimp/Importer.hpp>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

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

// The non-empty lines of an OFF file with comments ('#' to the end of the line) removed, as (line number,
// tokens).
class OffLines {
 public:
  explicit OffLines(std::istream& in) : m_in(in) {}
  // The next non-empty line's tokens; false at the end of the file.
  bool next(std::vector<std::string>& tokens) {
    std::string line;
    while (std::getline(m_in, line)) {
      ++m_number;
      const std::size_t hash = line.find('#');
      if (hash != std::string::npos) line.resize(hash);
      std::istringstream s(line);
      tokens.clear();
      for (std::string t; s >> t;) tokens.push_back(t);
      if (!tokens.empty()) return true;
    }
    return false;
  }
  long long lineNumber() const { return m_number; }

 private:
  std::istream& m_in;
  long long m_number = 0;
};

bool parseCount(const std::string& token, long long& out) {
  char* end = nullptr;
  errno = 0;
  out = std::strtoll(token.c_str(), &end, 10);
  return errno == 0 && end != token.c_str() && *end == '\0' && out >= 0;
}

// Assimp's OFF reader replaces a face index past the vertex count by the last vertex (with only a log line),
// so a corrupt face would load as a different mesh. This pass refuses it, naming the file, line and face.
// Anything it does not understand (binary OFF, a malformed header) is left to assimp's own checks.
void checkOffFaceIndices(const std::string& path) {
  std::ifstream in(path);
  OffLines lines(in);
  std::vector<std::string> tokens;
  if (!lines.next(tokens)) return;
  const std::string& keyword = tokens[0];
  if (keyword.size() < 3 || keyword.compare(keyword.size() - 3, 3, "OFF") != 0) return;
  if (keyword.find_first_of("n4") != std::string::npos) return;  // other dimensions: left to assimp
  std::vector<std::string> header(tokens.begin() + 1, tokens.end());
  if (!header.empty() && header[0] == "BINARY") return;
  while (header.size() < 3 && lines.next(tokens)) header.insert(header.end(), tokens.begin(), tokens.end());
  long long vertexCount = 0, faceCount = 0;
  if (header.size() < 2 || !parseCount(header[0], vertexCount) || !parseCount(header[1], faceCount)) return;
  for (long long v = 0; v < vertexCount; ++v) {
    if (!lines.next(tokens)) return;
  }
  for (long long f = 0; f < faceCount && lines.next(tokens); ++f) {
    long long corners = 0;
    if (!parseCount(tokens[0], corners)) return;
    for (long long c = 1; c <= corners && c < static_cast<long long>(tokens.size()); ++c) {
      long long index = 0;
      if (!parseCount(tokens[static_cast<std::size_t>(c)], index) || index >= vertexCount) {
        throw Error("mesh '" + path + "': line " + std::to_string(lines.lineNumber()) + ", face " + std::to_string(f) +
                    ": vertex index '" + tokens[static_cast<std::size_t>(c)] + "' is not in 0.." +
                    std::to_string(vertexCount - 1));
      }
    }
  }
}

bool hasOffExtension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return false;
  std::string ext = path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == "off";
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
  if (hasOffExtension(path)) checkOffFaceIndices(path);

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
