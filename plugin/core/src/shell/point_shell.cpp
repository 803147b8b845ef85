/// @file
/// @brief Point shells from meshes (vertices, particle repulsion) and shell files (see point_shell.h).
#include "sdfccd/shell/point_shell.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "sdfccd/error.h"
#include "sdfccd/output_file.h"
#include "sdfccd/parallel_for.h"

namespace sdfccd {
namespace {

// ---------------------------------------------------------------------------------------------------------
// Geometry helpers

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5). Written here because
// Eigen has no triangle queries and the core depends on Eigen alone.
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Cells of a uniform grid addressed by a packed 64-bit key; ids sorted by (cell, id) for a deterministic
// neighbour order.
class CellHash {
 public:
  CellHash(const Vec3& origin, double cellSize) : m_origin(origin), m_inverse(1.0 / cellSize) {}

  Vec3i cellOf(const Vec3& p) const {
    const Vec3 q = (p - m_origin) * m_inverse;
    return Vec3i(static_cast<int>(std::floor(q.x())), static_cast<int>(std::floor(q.y())),
                 static_cast<int>(std::floor(q.z())));
  }
  static std::uint64_t key(const Vec3i& c) {
    constexpr std::int64_t kBias = 1 << 20;
    return (static_cast<std::uint64_t>(c.x() + kBias) & 0x1fffff) |
           ((static_cast<std::uint64_t>(c.y() + kBias) & 0x1fffff) << 21) |
           ((static_cast<std::uint64_t>(c.z() + kBias) & 0x1fffff) << 42);
  }

  /// Builds from (key, id) pairs.
  void build(std::vector<std::pair<std::uint64_t, int>>& entries) {
    std::sort(entries.begin(), entries.end());
    m_ids.resize(entries.size());
    m_runs.clear();
    m_index.clear();
    for (std::size_t n = 0; n < entries.size(); ++n) {
      m_ids[n] = entries[n].second;
      if (n == 0 || entries[n].first != entries[n - 1].first) {
        m_runs.push_back({entries[n].first, static_cast<int>(n), static_cast<int>(n)});
      }
      m_runs.back().end = static_cast<int>(n + 1);
    }
    m_index.reserve(m_runs.size() * 2);
    for (std::size_t n = 0; n < m_runs.size(); ++n) m_index.emplace(m_runs[n].key, static_cast<int>(n));
  }

  struct Run {
    std::uint64_t key;
    int begin;
    int end;
  };
  const std::vector<Run>& runs() const { return m_runs; }
  const int* ids() const { return m_ids.data(); }
  /// The run of a cell, or null when empty.
  const Run* find(const Vec3i& cell) const {
    const auto it = m_index.find(key(cell));
    return it == m_index.end() ? nullptr : &m_runs[it->second];
  }

 private:
  Vec3 m_origin;
  double m_inverse;
  std::vector<int> m_ids;
  std::vector<Run> m_runs;
  std::unordered_map<std::uint64_t, int> m_index;
};

// The mesh's usable faces (non-zero area) with unit normals, and a cell hash over them for closest points.
struct SurfaceIndex {
  const TriangleMesh& mesh;
  std::vector<int> faces;     // usable faces
  std::vector<Vec3> normals;  // per usable face
  std::vector<double> areas;  // per usable face
  double totalArea = 0.0;
  CellHash hash;

  Vec3 origin;  // of the hash

  SurfaceIndex(const TriangleMesh& inMesh, const Vec3& inOrigin, double cellSize)
      : mesh(inMesh), hash(inOrigin, cellSize), origin(inOrigin) {}

  const Vec3& vertex(int face, int corner) const { return mesh.vertices[mesh.triangles[faces[face]][corner]]; }

  void buildHash(double cellSize) {
    std::vector<std::pair<std::uint64_t, int>> entries;
    const double halfDiagonal = 0.5 * std::sqrt(3.0) * cellSize;
    for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
      const Vec3& a = vertex(f, 0);
      const Vec3& b = vertex(f, 1);
      const Vec3& c = vertex(f, 2);
      const Vec3i lo = hash.cellOf(a.cwiseMin(b).cwiseMin(c));
      const Vec3i hi = hash.cellOf(a.cwiseMax(b).cwiseMax(c));
      for (int z = lo.z(); z <= hi.z(); ++z) {
        for (int y = lo.y(); y <= hi.y(); ++y) {
          for (int x = lo.x(); x <= hi.x(); ++x) {
            const Vec3 centre = origin + cellSize * (Vec3(x, y, z) + Vec3::Constant(0.5));
            if (std::abs(normals[f].dot(centre - a)) > halfDiagonal) continue;
            entries.emplace_back(CellHash::key(Vec3i(x, y, z)), f);
          }
        }
      }
    }
    hash.build(entries);
  }

  // Closest point on the surface to q; face `hint` bounds the search radius (it must be within one cell of q).
  void closest(const Vec3& q, int hint, Vec3& outPoint, int& outFace) const {
    Vec3 best = closestPointOnTriangle(q, vertex(hint, 0), vertex(hint, 1), vertex(hint, 2));
    double bestSq = (best - q).squaredNorm();
    int bestFace = hint;
    const double radius = std::sqrt(bestSq);
    const Vec3i lo = hash.cellOf(q - Vec3::Constant(radius));
    const Vec3i hi = hash.cellOf(q + Vec3::Constant(radius));
    for (int z = lo.z(); z <= hi.z(); ++z) {
      for (int y = lo.y(); y <= hi.y(); ++y) {
        for (int x = lo.x(); x <= hi.x(); ++x) {
          const CellHash::Run* run = hash.find(Vec3i(x, y, z));
          if (!run) continue;
          for (int n = run->begin; n < run->end; ++n) {
            const int f = hash.ids()[n];
            if (f == bestFace) continue;
            const Vec3 p = closestPointOnTriangle(q, vertex(f, 0), vertex(f, 1), vertex(f, 2));
            const double dSq = (p - q).squaredNorm();
            if (dSq < bestSq || (dSq == bestSq && f < bestFace)) {
              bestSq = dSq;
              best = p;
              bestFace = f;
            }
          }
        }
      }
    }
    outPoint = best;
    outFace = bestFace;
  }
};

void checkMesh(const TriangleMesh& mesh, const char* who) {
  if (mesh.vertices.empty() || mesh.triangles.empty()) throw Error(std::string(who) + ": the mesh is empty");
  const int count = static_cast<int>(mesh.vertices.size());
  for (const auto& v : mesh.vertices) {
    if (!v.allFinite()) throw Error(std::string(who) + ": the mesh has a non-finite vertex");
  }
  for (const auto& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      if (t[c] < 0 || t[c] >= count) throw Error(std::string(who) + ": a triangle index is out of range");
    }
  }
}

// ---------------------------------------------------------------------------------------------------------
// Files

std::string lowerExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

bool parseDouble(const std::string& token, double& out) {
  if (token.empty()) return false;
  char* end = nullptr;
  out = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size();
}

std::vector<std::string> splitTokens(const std::string& line, char separator) {
  std::vector<std::string> tokens;
  if (separator == ' ') {
    std::istringstream in(line);
    for (std::string t; in >> t;) tokens.push_back(t);
    return tokens;
  }
  std::string current;
  for (char ch : line) {
    if (ch == separator) {
      tokens.push_back(current);
      current.clear();
    } else if (ch != ' ' && ch != '\t' && ch != '\r') {
      current += ch;
    }
  }
  tokens.push_back(current);
  return tokens;
}

bool isBlank(const std::string& line) {
  return std::all_of(line.begin(), line.end(), [](char ch) { return std::isspace(static_cast<unsigned char>(ch)); });
}

// Checks and normalizes one point read from `where`.
void addPoint(PointShell& shell, const double v[6], const std::string& where) {
  const Vec3 p(v[0], v[1], v[2]);
  const Vec3 n(v[3], v[4], v[5]);
  if (!p.allFinite() || !n.allFinite()) throw Error(where + ": non-finite value");
  const double length = n.norm();
  if (!(length > 1e-12)) throw Error(where + ": zero-length normal");
  shell.positions.push_back(p);
  shell.normals.push_back(n / length);
}

PointShell loadPly(std::istream& in, const std::string& path) {
  std::string line;
  int lineNo = 0;
  auto next = [&](std::string& out) {
    if (!std::getline(in, out)) return false;
    ++lineNo;
    if (!out.empty() && out.back() == '\r') out.pop_back();
    return true;
  };
  if (!next(line) || line != "ply") throw Error(path + ": not a PLY file (no 'ply' magic on line 1)");
  long long count = -1;
  bool inVertex = false;
  bool vertexFirst = false;
  bool otherElements = false;
  std::vector<std::string> properties;
  bool ended = false;
  while (next(line)) {
    const auto tokens = splitTokens(line, ' ');
    if (tokens.empty() || tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    if (tokens[0] == "format") {
      if (tokens.size() < 2 || tokens[1] != "ascii") {
        throw Error(path + ":" + std::to_string(lineNo) + ": only ascii PLY shells are supported");
      }
    } else if (tokens[0] == "element") {
      if (tokens.size() != 3) throw Error(path + ":" + std::to_string(lineNo) + ": malformed element line");
      if (tokens[1] == "vertex") {
        if (otherElements) throw Error(path + ": the vertex element must come first");
        vertexFirst = true;
        inVertex = true;
        char* end = nullptr;
        count = std::strtoll(tokens[2].c_str(), &end, 10);
        if (end != tokens[2].c_str() + tokens[2].size() || count < 0) {
          throw Error(path + ":" + std::to_string(lineNo) + ": bad vertex count '" + tokens[2] + "'");
        }
      } else {
        inVertex = false;
        if (tokens[2] != "0") otherElements = true;
      }
    } else if (tokens[0] == "property") {
      if (inVertex) {
        if (tokens.size() != 3 || tokens[1] == "list") {
          throw Error(path + ":" + std::to_string(lineNo) + ": unsupported vertex property");
        }
        properties.push_back(tokens[2]);
      }
    } else if (tokens[0] == "end_header") {
      ended = true;
      break;
    } else {
      throw Error(path + ":" + std::to_string(lineNo) + ": unexpected header line '" + line + "'");
    }
  }
  if (!ended) throw Error(path + ": truncated PLY header (no end_header)");
  if (!vertexFirst || count < 0) throw Error(path + ": no vertex element");
  if (count == 0) throw Error(path + ": the shell has no points");
  if (count > 200000000) throw Error(path + ": absurd vertex count " + std::to_string(count));
  const char* names[6] = {"x", "y", "z", "nx", "ny", "nz"};
  int column[6];
  for (int k = 0; k < 6; ++k) {
    const auto it = std::find(properties.begin(), properties.end(), names[k]);
    if (it == properties.end()) throw Error(path + ": the vertex element has no '" + names[k] + "' property");
    column[k] = static_cast<int>(it - properties.begin());
  }
  PointShell shell;
  // The header's count is not trusted for memory: a 200-byte file claiming 10^8 points would reserve 5 GB
  // before its truncation is found (found by tests/fuzz/fuzz_shell_loader). The vectors grow as points come.
  const std::size_t reserved = static_cast<std::size_t>(std::min<long long>(count, 1 << 16));
  shell.positions.reserve(reserved);
  shell.normals.reserve(reserved);
  for (long long n = 0; n < count; ++n) {
    if (!next(line)) {
      throw Error(path + ": truncated, expected " + std::to_string(count) + " points, found " + std::to_string(n));
    }
    const auto tokens = splitTokens(line, ' ');
    const std::string where = path + ":" + std::to_string(lineNo);
    if (tokens.size() != properties.size()) {
      throw Error(where + ": expected " + std::to_string(properties.size()) + " values, found " +
                  std::to_string(tokens.size()));
    }
    double v[6];
    for (int k = 0; k < 6; ++k) {
      if (!parseDouble(tokens[column[k]], v[k])) throw Error(where + ": not a number '" + tokens[column[k]] + "'");
    }
    addPoint(shell, v, where);
  }
  if (!otherElements) {
    while (next(line)) {
      if (!isBlank(line)) {
        throw Error(path + ":" + std::to_string(lineNo) + ": more points than the header's " + std::to_string(count));
      }
    }
  }
  return shell;
}

PointShell loadCsv(std::istream& in, const std::string& path) {
  std::string line;
  int lineNo = 0;
  bool header = false;
  PointShell shell;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (isBlank(line)) continue;
    const auto tokens = splitTokens(line, ',');
    const std::string where = path + ":" + std::to_string(lineNo);
    if (!header) {
      if (tokens != std::vector<std::string>{"x", "y", "z", "nx", "ny", "nz"}) {
        throw Error(where + ": expected the header 'x,y,z,nx,ny,nz'");
      }
      header = true;
      continue;
    }
    if (tokens.size() != 6) throw Error(where + ": expected 6 values, found " + std::to_string(tokens.size()));
    double v[6];
    for (int k = 0; k < 6; ++k) {
      if (!parseDouble(tokens[k], v[k])) throw Error(where + ": not a number '" + tokens[k] + "'");
    }
    addPoint(shell, v, where);
  }
  if (!header) throw Error(path + ": empty file (no 'x,y,z,nx,ny,nz' header)");
  if (shell.empty()) throw Error(path + ": the shell has no points");
  return shell;
}

}  // namespace

void PointShell::validate() const {
  if (positions.size() != normals.size()) {
    throw Error("point shell: " + std::to_string(positions.size()) + " positions but " +
                std::to_string(normals.size()) + " normals");
  }
  for (std::size_t n = 0; n < positions.size(); ++n) {
    if (!positions[n].allFinite() || !normals[n].allFinite()) {
      throw Error("point shell: non-finite point or normal at index " + std::to_string(n));
    }
    if (std::abs(normals[n].norm() - 1.0) > 1e-6) {
      throw Error("point shell: normal " + std::to_string(n) + " is not of unit length");
    }
  }
}

PointShell shellFromVertices(const TriangleMesh& mesh) {
  checkMesh(mesh, "shellFromVertices");
  std::vector<Vec3> sums(mesh.vertices.size(), Vec3::Zero());
  for (const auto& t : mesh.triangles) {
    // |(b - a) x (c - a)| is twice the area: the sum is area weighted.
    const Vec3 areaVector =
        (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    for (int c = 0; c < 3; ++c) sums[t[c]] += areaVector;
  }
  PointShell shell;
  for (std::size_t v = 0; v < sums.size(); ++v) {
    const double length = sums[v].norm();
    if (!(length > 0.0)) continue;
    shell.positions.push_back(mesh.vertices[v]);
    shell.normals.push_back(sums[v] / length);
  }
  if (shell.empty()) throw Error("shellFromVertices: no vertex has a normal (all faces degenerate)");
  return shell;
}

PointShell sampleShell(const TriangleMesh& mesh, const ShellSamplingSettings& settings) {
  checkMesh(mesh, "sampleShell");
  if (settings.points < 1) throw Error("sampleShell: the number of points must be at least 1");
  if (settings.iterations < 0 || settings.iterations > 100000) throw Error("sampleShell: iterations out of range");
  if (!(settings.stepScale > 0.0) || !(settings.stepScale <= 1.0))
    throw Error("sampleShell: stepScale must be in (0, 1]");

  Box3 bounds;
  for (const auto& v : mesh.vertices) bounds.extend(v);
  // Usable faces and their areas.
  std::vector<int> faces;
  std::vector<Vec3> faceNormals;
  std::vector<double> areas;
  double totalArea = 0.0;
  for (int f = 0; f < static_cast<int>(mesh.triangles.size()); ++f) {
    const auto& t = mesh.triangles[f];
    const Vec3 areaVector =
        (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    const double twiceArea = areaVector.norm();
    if (!(twiceArea > 0.0)) continue;
    faces.push_back(f);
    faceNormals.push_back(areaVector / twiceArea);
    areas.push_back(0.5 * twiceArea);
    totalArea += 0.5 * twiceArea;
  }
  if (faces.empty() || !(totalArea > 0.0)) throw Error("sampleShell: the mesh has zero area");

  const int count = settings.points;
  const double radius = 2.0 * std::sqrt(totalArea / count);  // repulsion radius (Turk 1992)
  // Keep the cell hashes within 2^21 cells per axis.
  const double extent = bounds.sizes().maxCoeff();
  const double cellSize = std::max(0.5 * radius, extent * 1e-6 + 1e-300);
  const double pointCell = std::max(radius, extent / 1.0e6);

  SurfaceIndex surface(mesh, bounds.min(), cellSize);
  surface.faces = faces;
  surface.normals = faceNormals;
  surface.areas = areas;
  surface.totalArea = totalArea;

  // Area-weighted random samples, fixed seed.
  std::mt19937_64 rng(settings.seed);
  std::discrete_distribution<int> pickFace(areas.begin(), areas.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> positions(count);
  std::vector<int> onFace(count);
  for (int n = 0; n < count; ++n) {
    const int f = pickFace(rng);
    const double s = std::sqrt(unit(rng));
    const double r2 = unit(rng);
    positions[n] =
        (1.0 - s) * surface.vertex(f, 0) + s * (1.0 - r2) * surface.vertex(f, 1) + s * r2 * surface.vertex(f, 2);
    onFace[n] = f;
  }

  if (settings.iterations > 0) surface.buildHash(cellSize);
  std::vector<Vec3> moved(count);
  std::vector<int> movedFace(count);
  const double maxStep = 0.5 * radius;  // keeps the moved point within one triangle-hash cell of the surface
  const int threads = settings.threads;
  for (int iteration = 0; iteration < settings.iterations; ++iteration) {
    CellHash points(bounds.min(), pointCell);
    std::vector<std::pair<std::uint64_t, int>> entries(count);
    for (int n = 0; n < count; ++n) entries[n] = {CellHash::key(points.cellOf(positions[n])), n};
    points.build(entries);
    const auto& runs = points.runs();
    constexpr std::size_t kBlock = 64;
    const std::size_t blocks = (runs.size() + kBlock - 1) / kBlock;
    const double radiusSq = radius * radius;
    parallelFor(blocks, threads, [&](std::size_t block, int) {
      const std::size_t runEnd = std::min(runs.size(), (block + 1) * kBlock);
      for (std::size_t r = block * kBlock; r < runEnd; ++r) {
        const Vec3i cell = points.cellOf(positions[points.ids()[runs[r].begin]]);
        const CellHash::Run* neighbours[27];
        int neighbourCount = 0;
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
              if (const auto* run = points.find(cell + Vec3i(dx, dy, dz))) neighbours[neighbourCount++] = run;
        for (int k = runs[r].begin; k < runs[r].end; ++k) {
          const int i = points.ids()[k];
          const Vec3& xi = positions[i];
          Vec3 force = Vec3::Zero();
          for (int m = 0; m < neighbourCount; ++m) {
            for (int l = neighbours[m]->begin; l < neighbours[m]->end; ++l) {
              const int j = points.ids()[l];
              if (j == i) continue;
              const Vec3 delta = xi - positions[j];
              const double dSq = delta.squaredNorm();
              if (dSq >= radiusSq || dSq == 0.0) continue;
              const double d = std::sqrt(dSq);
              force += (1.0 - d / radius) / d * delta;
            }
          }
          const Vec3& normal = surface.normals[onFace[i]];
          force -= force.dot(normal) * normal;
          Vec3 step = settings.stepScale * radius * force;
          const double stepLength = step.norm();
          if (stepLength > maxStep) step *= maxStep / stepLength;
          surface.closest(xi + step, onFace[i], moved[i], movedFace[i]);
        }
      }
    });
    positions.swap(moved);
    onFace.swap(movedFace);
    if (settings.progress) settings.progress(static_cast<double>(iteration + 1) / settings.iterations);
  }

  PointShell shell;
  shell.positions = std::move(positions);
  shell.normals.resize(count);
  for (int n = 0; n < count; ++n) shell.normals[n] = surface.normals[onFace[n]];
  return shell;
}

void saveShell(const PointShell& shell, const std::string& path) {
  shell.validate();
  if (shell.empty()) throw Error("saveShell: the shell has no points");
  const std::string ext = lowerExtension(path);
  if (ext != "ply" && ext != "csv") throw Error(path + ": unknown shell format (use .ply or .csv)");
  OutputFile file(path);
  auto& out = file.stream();
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  if (ext == "ply") {
    out << "ply\nformat ascii 1.0\ncomment sdfccd point shell (body frame, unit outward normals)\n"
        << "element vertex " << shell.size() << "\n"
        << "property double x\nproperty double y\nproperty double z\n"
        << "property double nx\nproperty double ny\nproperty double nz\nend_header\n";
    for (std::size_t n = 0; n < shell.size(); ++n) {
      const Vec3& p = shell.positions[n];
      const Vec3& q = shell.normals[n];
      out << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << '\n';
    }
  } else {
    out << "x,y,z,nx,ny,nz\n";
    for (std::size_t n = 0; n < shell.size(); ++n) {
      const Vec3& p = shell.positions[n];
      const Vec3& q = shell.normals[n];
      out << p.x() << ',' << p.y() << ',' << p.z() << ',' << q.x() << ',' << q.y() << ',' << q.z() << '\n';
    }
  }
  file.commit();
}

PointShell parseShell(const std::string& text, const std::string& name) {
  const std::string ext = lowerExtension(name);
  if (ext != "ply" && ext != "csv") throw Error(name + ": unknown shell format (use .ply or .csv)");
  std::istringstream in(text);
  return ext == "ply" ? loadPly(in, name) : loadCsv(in, name);
}

PointShell loadShell(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext != "ply" && ext != "csv") throw Error(path + ": unknown shell format (use .ply or .csv)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the shell file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(path + ": cannot read the shell file");
  return parseShell(text.str(), path);
}

}  // namespace sdfccd
