/// @file
/// @brief blockWithHole: the peg-in-hole example's block (see procedural_shapes.h).
#include "sdfccd/haptics/procedural_shapes.h"

#include <cmath>
#include <vector>

#include "sdfccd/error.h"

namespace sdfccd::haptics {

namespace {

/// Builds triangles whose winding is chosen from the outward direction each face must have.
struct MeshBuilder {
  TriangleMesh mesh;

  int vertex(const Vec3& v) {
    mesh.vertices.push_back(v);
    return static_cast<int>(mesh.vertices.size()) - 1;
  }
  void triangle(int a, int b, int c, const Vec3& outward) {
    const Vec3& pa = mesh.vertices[static_cast<std::size_t>(a)];
    const Vec3 n =
        (mesh.vertices[static_cast<std::size_t>(b)] - pa).cross(mesh.vertices[static_cast<std::size_t>(c)] - pa);
    if (n.dot(outward) >= 0.0)
      mesh.triangles.push_back({a, b, c});
    else
      mesh.triangles.push_back({a, c, b});
  }
  void quad(int a, int b, int c, int d, const Vec3& outward) {  // a b c d around the quad
    triangle(a, b, c, outward);
    triangle(a, c, d, outward);
  }
};

}  // namespace

TriangleMesh blockWithHole(const Vec3& halfExtents, double holeRadius, int segments) {
  const double ax = halfExtents.x(), ay = halfExtents.y(), az = halfExtents.z();
  if (!(ax > 0.0 && ay > 0.0 && az > 0.0) || !halfExtents.allFinite() || !(holeRadius > 0.0))
    throw Error("block with hole: sizes must be positive and finite");
  if (!(holeRadius < std::min(ax, az))) throw Error("block with hole: the hole does not fit inside the block");
  if (segments < 3) throw Error("block with hole: segments must be >= 3");
  const double pi = std::acos(-1.0);
  const double step = 2.0 * pi / segments;
  // The rectangle's point on the ray at angle t (x = cos, z = sin).
  const auto onRectangle = [&](double t) {
    const double c = std::cos(t), s = std::sin(t);
    const double scale =
        std::min(std::abs(c) > 1e-300 ? ax / std::abs(c) : 1e300, std::abs(s) > 1e-300 ? az / std::abs(s) : 1e300);
    return Vec3(c * scale, 0.0, s * scale);
  };
  const double corners[4] = {std::atan2(az, ax), pi - std::atan2(az, ax), pi + std::atan2(az, ax),
                             2.0 * pi - std::atan2(az, ax)};
  MeshBuilder b;
  const Vec3 up = Vec3::UnitY();
  // Per sector i: the hole's two vertices (top and bottom) and the rectangle's points between its rays.
  std::vector<int> holeTop(static_cast<std::size_t>(segments)), holeBottom(static_cast<std::size_t>(segments));
  for (int i = 0; i < segments; ++i) {
    const Vec3 c(holeRadius * std::cos(i * step), 0.0, holeRadius * std::sin(i * step));
    holeTop[static_cast<std::size_t>(i)] = b.vertex(c + ay * up);
    holeBottom[static_cast<std::size_t>(i)] = b.vertex(c - ay * up);
  }
  std::vector<int> rimTop, rimBottom;  // the rectangle's ring, in angle order (ray points and corners)
  std::vector<int> rimOfRay(static_cast<std::size_t>(segments) + 1);
  for (int i = 0; i < segments; ++i) {
    const double t0 = i * step, t1 = (i + 1) * step;
    rimOfRay[static_cast<std::size_t>(i)] = static_cast<int>(rimTop.size());
    const Vec3 p = onRectangle(t0);
    rimTop.push_back(b.vertex(p + ay * up));
    rimBottom.push_back(b.vertex(p - ay * up));
    for (const double k : corners) {
      if (k > t0 + 1e-12 && k < t1 - 1e-12) {
        const Vec3 q = onRectangle(k);
        rimTop.push_back(b.vertex(q + ay * up));
        rimBottom.push_back(b.vertex(q - ay * up));
      }
    }
  }
  rimOfRay[static_cast<std::size_t>(segments)] = static_cast<int>(rimTop.size());  // wraps to 0
  const std::size_t rim = rimTop.size();
  for (int i = 0; i < segments; ++i) {
    const std::size_t a = static_cast<std::size_t>(i), an = static_cast<std::size_t>((i + 1) % segments);
    // Top and bottom faces: a fan from the hole's vertex i over the rectangle's points of the sector, then the
    // triangle to the hole's next vertex.
    const int first = rimOfRay[a], last = rimOfRay[a + 1];
    for (int k = first; k < last; ++k) {
      const std::size_t k0 = static_cast<std::size_t>(k), k1 = static_cast<std::size_t>(k + 1) % rim;
      b.triangle(holeTop[a], rimTop[k0], rimTop[k1], up);
      b.triangle(holeBottom[a], rimBottom[k0], rimBottom[k1], -up);
    }
    const std::size_t lastRim = static_cast<std::size_t>(last) % rim;
    b.triangle(holeTop[a], rimTop[lastRim], holeTop[an], up);
    b.triangle(holeBottom[a], rimBottom[lastRim], holeBottom[an], -up);
    // The hole's wall faces the axis.
    const Vec3 mid = 0.5 * (b.mesh.vertices[static_cast<std::size_t>(holeTop[a])] +
                            b.mesh.vertices[static_cast<std::size_t>(holeTop[an])]);
    b.quad(holeTop[a], holeTop[an], holeBottom[an], holeBottom[a], -Vec3(mid.x(), 0.0, mid.z()));
  }
  // The outer walls, face by face.
  for (std::size_t k = 0; k < rim; ++k) {
    const std::size_t k1 = (k + 1) % rim;
    const Vec3 mid = 0.5 * (b.mesh.vertices[static_cast<std::size_t>(rimTop[k])] +
                            b.mesh.vertices[static_cast<std::size_t>(rimTop[k1])]);
    const Vec3 outward = std::abs(mid.x()) / ax > std::abs(mid.z()) / az ? Vec3(std::copysign(1.0, mid.x()), 0, 0)
                                                                         : Vec3(0, 0, std::copysign(1.0, mid.z()));
    b.quad(rimTop[k], rimTop[k1], rimBottom[k1], rimBottom[k], outward);
  }
  return std::move(b.mesh);
}

}  // namespace sdfccd::haptics
