/// @file
/// @brief Point shells from meshes (vertices, particle repulsion) and their areas (see point_shell.h); shell files
/// are in shell_file.cpp.
#include "sdfccd/shell/point_shell.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <unordered_map>
#include <utility>

#include "mesh/triangle_distance.h"
#include "sdfccd/error.h"
#include "sdfccd/parallel_for.h"
#include "sdfccd/tolerances.h"

namespace sdfccd {
namespace {

// ---------------------------------------------------------------------------------------------------------
// Geometry helpers

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
    Vec3 best = detail::closestPointOnTriangle(q, vertex(hint, 0), vertex(hint, 1), vertex(hint, 2));
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
            const Vec3 p = detail::closestPointOnTriangle(q, vertex(f, 0), vertex(f, 1), vertex(f, 2));
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
    if (std::abs(normals[n].norm() - 1.0) > tolerance::kUnitNormalTolerance) {
      throw Error("point shell: normal " + std::to_string(n) + " is not of unit length");
    }
  }
  if (areas.empty()) return;
  if (areas.size() != positions.size()) {
    throw Error("point shell: " + std::to_string(positions.size()) + " positions but " + std::to_string(areas.size()) +
                " areas");
  }
  for (std::size_t n = 0; n < areas.size(); ++n) {
    if (!(areas[n] > 0.0) || !std::isfinite(areas[n])) {
      throw Error("point shell: area " + std::to_string(n) + " is not positive and finite");
    }
  }
}

double PointShell::totalArea() const {
  double sum = 0.0;
  for (double a : areas) sum += a;
  return sum;
}

namespace {

/// The typical point spacing of a shell: from the mean area per point when known, else from its bounding box's
/// surface.
double typicalPointSpacing(const PointShell& shell) {
  if (shell.hasAreas()) {
    const double perPoint = shell.totalArea() / double(shell.size());
    if (perPoint > 0.0 && std::isfinite(perPoint)) return std::sqrt(perPoint);
  }
  Vec3 lo = shell.positions[0], hi = shell.positions[0];
  for (const Vec3& p : shell.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Vec3 e = hi - lo;
  const double boxArea = 2.0 * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
  return std::sqrt(std::max(boxArea, 1e-300) / double(shell.size()));
}

}  // namespace

std::vector<double> shellCurvatures(const PointShell& shell) {
  std::vector<double> curvature(shell.size(), 0.0);
  if (shell.size() < 2) return curvature;
  const double radius = 1.5 * typicalPointSpacing(shell);
  if (!(radius > 0.0) || !std::isfinite(radius)) return curvature;
  // Cells one radius wide: a point's neighbours lie in the 27 cells around its own.
  CellHash hash(Vec3::Zero(), radius);
  std::vector<std::pair<std::uint64_t, int>> entries;
  entries.reserve(shell.size());
  for (std::size_t i = 0; i < shell.size(); ++i) {
    entries.emplace_back(CellHash::key(hash.cellOf(shell.positions[i])), static_cast<int>(i));
  }
  hash.build(entries);
  const double radiusSquared = radius * radius;
  for (std::size_t i = 0; i < shell.size(); ++i) {
    const Vec3& p = shell.positions[i];
    const Vec3i cell = hash.cellOf(p);
    double largest = 0.0;
    for (int z = cell.z() - 1; z <= cell.z() + 1; ++z) {
      for (int y = cell.y() - 1; y <= cell.y() + 1; ++y) {
        for (int x = cell.x() - 1; x <= cell.x() + 1; ++x) {
          const CellHash::Run* run = hash.find(Vec3i(x, y, z));
          if (!run) continue;
          for (int n = run->begin; n < run->end; ++n) {
            const std::size_t j = static_cast<std::size_t>(hash.ids()[n]);
            const double squared = (shell.positions[j] - p).squaredNorm();
            if (j == i || !(squared > 0.0) || squared > radiusSquared) continue;
            largest = std::max(largest, angleBetween(shell.normals[i], shell.normals[j]) / std::sqrt(squared));
          }
        }
      }
    }
    curvature[i] = largest;
  }
  return curvature;
}

void assignUniformAreas(PointShell& shell, double totalArea) {
  if (shell.empty()) throw Error("assignUniformAreas: the shell has no points");
  if (!(totalArea > 0.0) || !std::isfinite(totalArea)) {
    throw Error("assignUniformAreas: totalArea must be positive and finite");
  }
  shell.areas.assign(shell.size(), totalArea / static_cast<double>(shell.size()));
}

PointShell shellFromVertices(const TriangleMesh& mesh) {
  checkMesh(mesh, "shellFromVertices");
  std::vector<Vec3> sums(mesh.vertices.size(), Vec3::Zero());
  std::vector<double> thirds(mesh.vertices.size(), 0.0);  // barycentric vertex areas
  for (const auto& t : mesh.triangles) {
    // |(b - a) x (c - a)| is twice the area: the sum is area weighted.
    const Vec3 areaVector =
        (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    const double third = areaVector.norm() / 6.0;
    for (int c = 0; c < 3; ++c) {
      sums[t[c]] += areaVector;
      thirds[t[c]] += third;
    }
  }
  PointShell shell;
  for (std::size_t v = 0; v < sums.size(); ++v) {
    const double length = sums[v].norm();
    if (!(length > 0.0)) continue;
    shell.positions.push_back(mesh.vertices[v]);
    shell.normals.push_back(sums[v] / length);
    shell.areas.push_back(thirds[v]);
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
  assignUniformAreas(shell, totalArea);
  return shell;
}

}  // namespace sdfccd
