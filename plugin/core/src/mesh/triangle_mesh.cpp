/// @file
/// @brief TriangleMesh measures and repairMesh: merge, drop degenerate/duplicate faces, compact, orient.
///
/// @details Everything is O(n log n) (sorting) or expected O(n) (hashing); no pairwise vertex loops.
#include "sdfccd/mesh/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "sdfccd/error.h"
#include "sdfccd/tolerances.h"

namespace sdfccd {

Box3 TriangleMesh::bounds() const {
  Box3 box;  // Eigen's default box is empty
  for (const Vec3& v : vertices) box.extend(v);
  return box;
}

double TriangleMesh::signedVolume() const {
  double sixTimes = 0.0;
  for (const auto& t : triangles) {
    sixTimes += vertices[t[0]].dot(vertices[t[1]].cross(vertices[t[2]]));
  }
  return sixTimes / 6.0;
}

double TriangleMesh::area() const {
  double twice = 0.0;
  for (const auto& t : triangles) {
    twice += (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]).norm();
  }
  return 0.5 * twice;
}

std::string MeshRepairReport::summary() const {
  std::ostringstream s;
  bool any = false;
  auto item = [&](int count, const char* what) {
    if (count == 0) return;
    s << (any ? ", " : "") << what << " " << count;
    any = true;
  };
  item(mergedVertices, "merged vertices");
  item(droppedDegenerate, "dropped degenerate faces");
  item(droppedDuplicates, "dropped duplicate faces");
  item(reorientedFaces, "reoriented faces");
  item(unreferencedVertices, "removed unreferenced vertices");
  if (!any) s << "no repairs";
  s << "; " << components << (components == 1 ? " component, " : " components, ");
  if (closed) {
    s << "closed";
  } else {
    s << "open (" << boundaryEdges << " boundary edges, " << nonManifoldEdges << " non-manifold edges)";
  }
  return s.str();
}

namespace {

// Maps each vertex to a representative (the first vertex at the same position, or within `tolerance`).
std::vector<int> mergeVertices(const std::vector<Vec3>& vertices, double tolerance) {
  const int n = static_cast<int>(vertices.size());
  std::vector<int> representative(static_cast<std::size_t>(n));
  if (tolerance <= 0.0) {
    // Exact duplicates: sort lexicographically (stable, so the first index of each run represents it).
    std::vector<int> order(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    auto less = [&](int a, int b) {
      const Vec3& p = vertices[a];
      const Vec3& q = vertices[b];
      if (p.x() != q.x()) return p.x() < q.x();
      if (p.y() != q.y()) return p.y() < q.y();
      return p.z() < q.z();
    };
    std::stable_sort(order.begin(), order.end(), less);
    for (std::size_t s = 0; s < order.size();) {
      std::size_t e = s + 1;
      while (e < order.size() && vertices[order[e]] == vertices[order[s]]) ++e;
      int first = order[s];
      for (std::size_t m = s; m < e; ++m) first = std::min(first, order[m]);
      for (std::size_t m = s; m < e; ++m) representative[order[m]] = first;
      s = e;
    }
    return representative;
  }
  // Within a tolerance: a hash grid with cells of the tolerance's size; each vertex looks at the 27 cells
  // around it for an earlier representative within the tolerance.
  struct KeyHash {
    std::size_t operator()(const Vec3i& k) const {
      return static_cast<std::size_t>(k.x()) * 73856093u ^ static_cast<std::size_t>(k.y()) * 19349663u ^
             static_cast<std::size_t>(k.z()) * 83492791u;
    }
  };
  struct KeyEq {
    bool operator()(const Vec3i& a, const Vec3i& b) const { return a == b; }
  };
  const Box3 box = [&] {
    Box3 b;
    for (const Vec3& v : vertices) b.extend(v);
    return b;
  }();
  std::unordered_map<Vec3i, std::vector<int>, KeyHash, KeyEq> cells;
  cells.reserve(vertices.size());
  const double tol2 = tolerance * tolerance;
  for (int v = 0; v < n; ++v) {
    const Vec3 u = (vertices[v] - box.min()) / tolerance;
    const Vec3i key(static_cast<int>(std::floor(u.x())), static_cast<int>(std::floor(u.y())),
                    static_cast<int>(std::floor(u.z())));
    int found = -1;
    for (int dz = -1; dz <= 1 && found < 0; ++dz)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dx = -1; dx <= 1 && found < 0; ++dx) {
          const auto it = cells.find(key + Vec3i(dx, dy, dz));
          if (it == cells.end()) continue;
          for (int r : it->second) {
            if ((vertices[r] - vertices[v]).squaredNorm() <= tol2) {
              found = r;
              break;
            }
          }
        }
    if (found >= 0) {
      representative[v] = found;
    } else {
      representative[v] = v;
      cells[key].push_back(v);
    }
  }
  return representative;
}

struct HalfEdge {
  int lo, hi;  // sorted vertex indices of the edge
  int face;
  bool forward;  // the face traverses lo -> hi
};

// Edges grouped by (lo, hi): returns the half-edges sorted so that each run shares one edge.
std::vector<HalfEdge> sortedHalfEdges(const std::vector<std::array<int, 3>>& triangles) {
  std::vector<HalfEdge> edges;
  edges.reserve(triangles.size() * 3);
  for (int f = 0; f < static_cast<int>(triangles.size()); ++f) {
    for (int e = 0; e < 3; ++e) {
      const int a = triangles[f][e], b = triangles[f][(e + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), f, a < b});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.lo != y.lo ? x.lo < y.lo : (x.hi != y.hi ? x.hi < y.hi : x.face < y.face);
  });
  return edges;
}

int findRoot(std::vector<int>& parent, int x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

}  // namespace

void checkMesh(const TriangleMesh& mesh, const std::string& who) {
  if (mesh.vertices.empty() || mesh.triangles.empty())
    throw Error(who + ": the mesh is empty (no vertices or no faces)");
  const int vertexCount = static_cast<int>(mesh.vertices.size());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!mesh.vertices[v].allFinite()) throw Error(who + ": mesh vertex " + std::to_string(v) + " is not finite");
  }
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int c : mesh.triangles[f]) {
      if (c < 0 || c >= vertexCount) {
        throw Error(who + ": mesh face " + std::to_string(f) + " has vertex index " + std::to_string(c) +
                    " out of range");
      }
    }
  }
}

MeshRepairReport repairMesh(TriangleMesh& ioMesh, const MeshRepairSettings& settings) {
  MeshRepairReport report;
  checkMesh(ioMesh, "mesh repair");
  const int vertexCount = static_cast<int>(ioMesh.vertices.size());
  if (!(settings.mergeTolerance >= 0.0) || !std::isfinite(settings.mergeTolerance)) {
    throw Error("merge tolerance must be finite and non-negative");
  }

  // 1. Merge duplicate vertices.
  const std::vector<int> representative = mergeVertices(ioMesh.vertices, settings.mergeTolerance);
  for (int v = 0; v < vertexCount; ++v) report.mergedVertices += representative[v] != v ? 1 : 0;

  // 2. Drop degenerate faces (repeated index, or area negligible against the longest edge: sin of the
  //    largest angle below 1e-12, i.e. collinear to double rounding) and duplicate faces (same vertex set).
  std::vector<std::array<int, 3>> kept;
  kept.reserve(ioMesh.triangles.size());
  for (const auto& t : ioMesh.triangles) {
    const std::array<int, 3> r{representative[t[0]], representative[t[1]], representative[t[2]]};
    if (r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) {
      ++report.droppedDegenerate;
      continue;
    }
    const Vec3& a = ioMesh.vertices[r[0]];
    const Vec3& b = ioMesh.vertices[r[1]];
    const Vec3& c = ioMesh.vertices[r[2]];
    const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if ((b - a).cross(c - a).norm() <= tolerance::kCollinearity * longest2) {
      ++report.droppedDegenerate;
      continue;
    }
    kept.push_back(r);
  }
  {
    std::vector<std::size_t> order(kept.size());
    std::iota(order.begin(), order.end(), 0);
    auto sortedKey = [&](std::size_t f) {
      std::array<int, 3> k = kept[f];
      std::sort(k.begin(), k.end());
      return k;
    };
    std::vector<std::array<int, 3>> keys(kept.size());
    for (std::size_t f = 0; f < kept.size(); ++f) keys[f] = sortedKey(f);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return keys[x] < keys[y]; });
    std::vector<char> drop(kept.size(), 0);
    for (std::size_t s = 1; s < order.size(); ++s) {
      if (keys[order[s]] == keys[order[s - 1]]) drop[order[s]] = 1;
    }
    std::vector<std::array<int, 3>> unique;
    unique.reserve(kept.size());
    for (std::size_t f = 0; f < kept.size(); ++f) {
      if (drop[f]) {
        ++report.droppedDuplicates;
      } else {
        unique.push_back(kept[f]);
      }
    }
    kept.swap(unique);
  }
  if (kept.empty()) throw Error("mesh has no faces left after dropping degenerate faces");

  // 3. Remove vertices no face uses (merged-away vertices are counted as merged, not here). The kept
  //    vertices keep their relative order, so a clean mesh comes out unchanged.
  std::vector<int> newIndex(static_cast<std::size_t>(vertexCount), -1);
  for (const auto& t : kept) {
    for (int c : t) newIndex[c] = 0;
  }
  std::vector<Vec3> vertices;
  for (int v = 0; v < vertexCount; ++v) {
    if (newIndex[v] < 0) continue;
    newIndex[v] = static_cast<int>(vertices.size());
    vertices.push_back(ioMesh.vertices[v]);
  }
  for (auto& t : kept) {
    for (int& c : t) c = newIndex[c];
  }
  int representatives = 0;
  for (int v = 0; v < vertexCount; ++v) representatives += representative[v] == v ? 1 : 0;
  report.unreferencedVertices = representatives - static_cast<int>(vertices.size());

  // 4. Edge topology: boundary and non-manifold edges, components (faces sharing any edge).
  const int faceCount = static_cast<int>(kept.size());
  const std::vector<HalfEdge> edges = sortedHalfEdges(kept);
  std::vector<int> parent(static_cast<std::size_t>(faceCount));
  std::iota(parent.begin(), parent.end(), 0);
  // Manifold adjacency for the orientation walk: neighbour across each edge, and whether the two faces
  // traverse it in the same direction (then one of them must flip).
  std::vector<std::array<int, 3>> neighbour(static_cast<std::size_t>(faceCount), {-1, -1, -1});
  std::vector<std::array<char, 3>> sameDirection(static_cast<std::size_t>(faceCount), {0, 0, 0});
  std::vector<int> slot(static_cast<std::size_t>(faceCount), 0);
  for (std::size_t s = 0; s < edges.size();) {
    std::size_t e = s + 1;
    while (e < edges.size() && edges[e].lo == edges[s].lo && edges[e].hi == edges[s].hi) ++e;
    const std::size_t uses = e - s;
    if (uses == 1) ++report.boundaryEdges;
    if (uses > 2) ++report.nonManifoldEdges;
    for (std::size_t m = s + 1; m < e; ++m) {
      parent[findRoot(parent, edges[m].face)] = findRoot(parent, edges[s].face);
    }
    if (uses == 2) {
      const HalfEdge& x = edges[s];
      const HalfEdge& y = edges[s + 1];
      const char same = x.forward == y.forward ? 1 : 0;
      if (slot[x.face] < 3 && slot[y.face] < 3) {
        neighbour[x.face][slot[x.face]] = y.face;
        sameDirection[x.face][slot[x.face]++] = same;
        neighbour[y.face][slot[y.face]] = x.face;
        sameDirection[y.face][slot[y.face]++] = same;
      }
    }
    s = e;
  }
  std::vector<int> componentOf(static_cast<std::size_t>(faceCount));
  {
    std::unordered_map<int, int> rootToComponent;
    for (int f = 0; f < faceCount; ++f) {
      const int root = findRoot(parent, f);
      auto [it, inserted] = rootToComponent.emplace(root, static_cast<int>(rootToComponent.size()));
      componentOf[f] = it->second;
    }
    report.components = static_cast<int>(rootToComponent.size());
  }

  // 5. Orientation: BFS over manifold edges; each face gets a flip bit relative to its patch's seed. A patch
  //    keeps the orientation of the majority of its faces; a patch that is closed is then flipped if its
  //    volume is negative. Non-orientable patches (Moebius) keep the first consistent assignment found.
  std::vector<char> flip(static_cast<std::size_t>(faceCount), 0);
  bool inconsistent = false;
  if (settings.orient) {
    std::vector<char> visited(static_cast<std::size_t>(faceCount), 0);
    std::vector<int> queue;
    std::vector<char> componentHasBoundary(static_cast<std::size_t>(report.components), 0);
    for (std::size_t s = 0; s < edges.size();) {
      std::size_t e = s + 1;
      while (e < edges.size() && edges[e].lo == edges[s].lo && edges[e].hi == edges[s].hi) ++e;
      if (e - s != 2) componentHasBoundary[componentOf[edges[s].face]] = 1;
      s = e;
    }
    for (int seed = 0; seed < faceCount; ++seed) {
      if (visited[seed]) continue;
      queue.clear();
      queue.push_back(seed);
      visited[seed] = 1;
      for (std::size_t q = 0; q < queue.size(); ++q) {
        const int f = queue[q];
        for (int n = 0; n < 3; ++n) {
          const int g = neighbour[f][n];
          if (g < 0) continue;
          const char wanted = static_cast<char>(flip[f] ^ sameDirection[f][n]);
          if (!visited[g]) {
            visited[g] = 1;
            flip[g] = wanted;
            queue.push_back(g);
          } else if (flip[g] != wanted) {
            inconsistent = true;
          }
        }
      }
      std::size_t flipped = 0;
      for (int f : queue) flipped += flip[f] ? 1 : 0;
      const bool invertPatch = 2 * flipped > queue.size();
      if (invertPatch) {
        for (int f : queue) flip[f] = static_cast<char>(!flip[f]);
      }
      // A closed patch (its component has only manifold edges and the patch is the whole component)
      // must enclose positive volume.
      if (!componentHasBoundary[componentOf[seed]]) {
        double sixVolume = 0.0;
        for (int f : queue) {
          const auto& t = kept[f];
          const double v = vertices[t[0]].dot(vertices[t[1]].cross(vertices[t[2]]));
          sixVolume += flip[f] ? -v : v;
        }
        if (sixVolume < 0.0) {
          for (int f : queue) flip[f] = static_cast<char>(!flip[f]);
        }
      }
    }
    for (int f = 0; f < faceCount; ++f) {
      if (flip[f]) {
        std::swap(kept[f][1], kept[f][2]);
        ++report.reorientedFaces;
      }
    }
  } else {
    for (int f = 0; f < faceCount; ++f)
      for (int n = 0; n < 3; ++n) inconsistent |= neighbour[f][n] >= 0 && sameDirection[f][n];
  }
  report.closed = report.boundaryEdges == 0 && report.nonManifoldEdges == 0 && !inconsistent;

  ioMesh.vertices.swap(vertices);
  ioMesh.triangles.swap(kept);
  return report;
}

}  // namespace sdfccd
