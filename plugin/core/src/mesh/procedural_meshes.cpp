/// @file
/// @brief Procedural closed meshes (see procedural_meshes.h).
#include "sdfccd/mesh/procedural_meshes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

// Signed volume by the divergence theorem; computed here so that the generators do not depend on the mesh
// module's translation unit.
double volumeOf(const TriangleMesh& mesh) {
  double sum = 0.0;
  for (const auto& t : mesh.triangles) {
    sum += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  }
  return sum / 6.0;
}

void orientOutward(TriangleMesh& mesh) {
  if (volumeOf(mesh) < 0.0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
}

// Revolves a profile (r, y) about the y axis. Profile points with r == 0 must be the first and/or last one
// (poles); they become a single vertex.
TriangleMesh lathe(const std::vector<std::pair<double, double>>& profile, int segments) {
  TriangleMesh mesh;
  const int n = static_cast<int>(profile.size());
  std::vector<int> ringStart(n, -1);  // first vertex of ring i, or the pole vertex
  std::vector<bool> pole(n, false);
  for (int i = 0; i < n; ++i) {
    const double r = profile[i].first;
    const double y = profile[i].second;
    ringStart[i] = static_cast<int>(mesh.vertices.size());
    if (r == 0.0) {
      pole[i] = true;
      mesh.vertices.emplace_back(0.0, y, 0.0);
      continue;
    }
    for (int j = 0; j < segments; ++j) {
      const double phi = 2.0 * kPi * j / segments;
      mesh.vertices.emplace_back(r * std::cos(phi), y, r * std::sin(phi));
    }
  }
  for (int i = 0; i + 1 < n; ++i) {
    for (int j = 0; j < segments; ++j) {
      const int jn = (j + 1) % segments;
      const int a = pole[i] ? ringStart[i] : ringStart[i] + j;
      const int b = pole[i] ? ringStart[i] : ringStart[i] + jn;
      const int c = pole[i + 1] ? ringStart[i + 1] : ringStart[i + 1] + j;
      const int d = pole[i + 1] ? ringStart[i + 1] : ringStart[i + 1] + jn;
      if (!pole[i]) mesh.triangles.push_back({a, b, d});
      if (!pole[i + 1]) mesh.triangles.push_back({a, d, c});
      if (pole[i] && pole[i + 1]) throw Error("lathe profile: two consecutive points on the axis");
    }
  }
  orientOutward(mesh);
  return mesh;
}

}  // namespace

TriangleMesh makeBox(const Vec3& halfExtents) {
  if (!(halfExtents.array() > 0.0).all() || !halfExtents.allFinite()) {
    throw Error("makeBox: half extents must be positive and finite");
  }
  TriangleMesh mesh;
  for (int k = 0; k < 8; ++k) {
    mesh.vertices.emplace_back((k & 1 ? 1.0 : -1.0) * halfExtents.x(), (k & 2 ? 1.0 : -1.0) * halfExtents.y(),
                               (k & 4 ? 1.0 : -1.0) * halfExtents.z());
  }
  // Two triangles per face, counter-clockwise seen from outside.
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces) {
    mesh.triangles.push_back({f[0], f[1], f[2]});
    mesh.triangles.push_back({f[0], f[2], f[3]});
  }
  orientOutward(mesh);
  return mesh;
}

TriangleMesh makeIcosphere(double radius, int subdivisions) {
  if (!(radius > 0.0) || !std::isfinite(radius)) throw Error("makeIcosphere: radius must be positive and finite");
  if (subdivisions < 0 || subdivisions > 8) throw Error("makeIcosphere: subdivisions must be in [0, 8]");
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh mesh;
  mesh.vertices = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  mesh.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& v : mesh.vertices) v.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoints;
    auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      const int index = static_cast<int>(mesh.vertices.size());
      mesh.vertices.push_back((mesh.vertices[a] + mesh.vertices[b]).normalized());
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<std::array<int, 3>> next;
    next.reserve(mesh.triangles.size() * 4);
    for (const auto& tri : mesh.triangles) {
      const int ab = midpoint(tri[0], tri[1]);
      const int bc = midpoint(tri[1], tri[2]);
      const int ca = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], ab, ca});
      next.push_back({tri[1], bc, ab});
      next.push_back({tri[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    mesh.triangles = std::move(next);
  }
  for (auto& v : mesh.vertices) v *= radius;
  orientOutward(mesh);
  return mesh;
}

TriangleMesh makeCylinder(double radius, double height, int segments) {
  if (!(radius > 0.0) || !(height > 0.0) || !std::isfinite(radius) || !std::isfinite(height)) {
    throw Error("makeCylinder: radius and height must be positive and finite");
  }
  if (segments < 3) throw Error("makeCylinder: at least 3 segments");
  const double h = 0.5 * height;
  return lathe({{0.0, -h}, {radius, -h}, {radius, h}, {0.0, h}}, segments);
}

TriangleMesh makeLathedBowl(const LathedBowlSettings& s) {
  const double values[] = {s.rimRadius, s.height, s.wall, s.footRadius, s.footHeight};
  for (double v : values) {
    if (!(v > 0.0) || !std::isfinite(v)) throw Error("makeLathedBowl: sizes must be positive and finite");
  }
  if (s.segments < 3 || s.profileSamples < 2) throw Error("makeLathedBowl: at least 3 segments and 2 profile samples");
  if (s.footRadius <= s.wall || s.footRadius + 2.0 * s.wall >= s.rimRadius || s.footHeight + 3.0 * s.wall >= s.height) {
    throw Error("makeLathedBowl: the wall is too thick or the foot too large for the bowl");
  }
  const double yb = -0.5 * s.height;                // bottom of the foot ring
  const double yt = 0.5 * s.height - 0.5 * s.wall;  // centre line of the rounded rim
  const double y0 = yb + s.footHeight;              // where the curved outer wall starts
  const double w = s.wall;
  const double rf = s.footRadius;
  const double rr = s.rimRadius;
  std::vector<std::pair<double, double>> profile;
  // Underside: recessed disc inside the foot ring, then the foot ring.
  profile.emplace_back(0.0, yb + 0.5 * s.footHeight);
  profile.emplace_back(rf - w, yb + 0.5 * s.footHeight);
  profile.emplace_back(rf - w, yb);
  profile.emplace_back(rf, yb);
  profile.emplace_back(rf, y0);
  // Outer wall: a quarter ellipse from the foot to the rim.
  for (int k = 1; k <= s.profileSamples; ++k) {
    const double a = 0.5 * kPi * k / s.profileSamples;
    profile.emplace_back(rf + (rr - rf) * std::sin(a), y0 + (yt - y0) * (1.0 - std::cos(a)));
  }
  // Rounded rim: a half circle over the wall.
  const int rimSamples = 6;
  for (int k = 1; k < rimSamples; ++k) {
    const double a = kPi * k / rimSamples;
    profile.emplace_back(rr - 0.5 * w + 0.5 * w * std::cos(a), yt + 0.5 * w * std::sin(a));
  }
  // Inner wall back down to the inside of the bottom.
  const double yi = y0 + w;
  for (int k = s.profileSamples; k >= 0; --k) {
    const double a = 0.5 * kPi * k / s.profileSamples;
    profile.emplace_back(rf + (rr - w - rf) * std::sin(a), yi + (yt - yi) * (1.0 - std::cos(a)));
  }
  profile.emplace_back(0.0, yi);
  return lathe(profile, s.segments);
}

}  // namespace sdfccd
