/// @file
/// @brief makeSweptTube (see swept_tube.h).
#include "sdfccd/model/swept_tube.h"

#include <algorithm>
#include <cmath>

#include "sdfccd/error.h"

namespace sdfccd {

double polylineLength(const std::vector<Vec3>& curve) {
  double length = 0.0;
  for (std::size_t i = 1; i < curve.size(); ++i) length += (curve[i] - curve[i - 1]).norm();
  return length;
}

std::vector<Vec3> resamplePolylineByLength(const std::vector<Vec3>& curve, int samples) {
  if (curve.size() < 2) throw Error("resamplePolylineByLength: need at least 2 points");
  if (samples < 2) throw Error("resamplePolylineByLength: need at least 2 samples");
  for (const Vec3& p : curve)
    if (!p.allFinite()) throw Error("resamplePolylineByLength: non-finite point");
  const double length = polylineLength(curve);
  if (!(length > 0.0)) throw Error("resamplePolylineByLength: the polyline has zero length");
  std::vector<Vec3> out;
  out.reserve(static_cast<std::size_t>(samples));
  out.push_back(curve.front());
  std::size_t segment = 1;
  double before = 0.0;  // length up to curve[segment - 1]
  for (int k = 1; k + 1 < samples; ++k) {
    const double at = length * k / (samples - 1);
    while (segment + 1 < curve.size() && before + (curve[segment] - curve[segment - 1]).norm() < at) {
      before += (curve[segment] - curve[segment - 1]).norm();
      ++segment;
    }
    const double piece = (curve[segment] - curve[segment - 1]).norm();
    const double u = piece > 0.0 ? std::clamp((at - before) / piece, 0.0, 1.0) : 0.0;
    out.push_back(curve[segment - 1] + u * (curve[segment] - curve[segment - 1]));
  }
  out.push_back(curve.back());
  return out;
}

TriangleMesh makeSweptTube(const std::vector<Vec3>& curve, double radius, int segments) {
  const int n = static_cast<int>(curve.size());
  if (n < 2) throw Error("makeSweptTube: the curve needs at least 2 samples");
  if (!(radius > 0.0) || !std::isfinite(radius)) throw Error("makeSweptTube: radius must be positive and finite");
  if (segments < 3) throw Error("makeSweptTube: need at least 3 segments");
  for (int i = 0; i < n; ++i) {
    if (!curve[static_cast<std::size_t>(i)].allFinite()) throw Error("makeSweptTube: non-finite curve sample");
    if (i > 0 && !((curve[static_cast<std::size_t>(i)] - curve[static_cast<std::size_t>(i - 1)]).norm() > 0.0))
      throw Error("makeSweptTube: two consecutive curve samples coincide");
  }
  const auto sample = [&](int i) -> const Vec3& { return curve[static_cast<std::size_t>(i)]; };

  // Unit tangents: central differences inside, one-sided at the ends.
  std::vector<Vec3> tangents(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Vec3 d = sample(std::min(i + 1, n - 1)) - sample(std::max(i - 1, 0));
    if (!(d.norm() > 0.0)) throw Error("makeSweptTube: the curve folds back onto itself");
    tangents[static_cast<std::size_t>(i)] = d.normalized();
  }
  // The first ring's reference direction: any unit vector normal to the first tangent.
  Vec3 normal = tangents[0].unitOrthogonal();

  TriangleMesh mesh;
  mesh.vertices.reserve(static_cast<std::size_t>(n * segments + 2));
  for (int i = 0; i < n; ++i) {
    const Vec3& t = tangents[static_cast<std::size_t>(i)];
    if (i > 0) {
      // Parallel transport: the smallest rotation taking the previous tangent to this one.
      normal = Quat::FromTwoVectors(tangents[static_cast<std::size_t>(i - 1)], t) * normal;
      normal = (normal - normal.dot(t) * t).normalized();  // remove rounding drift
    }
    const Vec3 binormal = t.cross(normal);
    for (int j = 0; j < segments; ++j) {
      const double a = 2.0 * kPi * j / segments;
      mesh.vertices.push_back(sample(i) + radius * (std::cos(a) * normal + std::sin(a) * binormal));
    }
  }
  // With (normal, binormal, tangent) right-handed, ring vertices run counter-clockwise seen from the tip of the
  // tangent: (j, j+1 on ring i+1, j on ring i+1) faces outward.
  const auto ring = [&](int i, int j) { return i * segments + (j % segments); };
  for (int i = 0; i + 1 < n; ++i) {
    for (int j = 0; j < segments; ++j) {
      mesh.triangles.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
      mesh.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
    }
  }
  // Caps: the start cap faces -tangent, the end cap +tangent.
  const int startCentre = static_cast<int>(mesh.vertices.size());
  mesh.vertices.push_back(sample(0));
  const int endCentre = startCentre + 1;
  mesh.vertices.push_back(sample(n - 1));
  for (int j = 0; j < segments; ++j) {
    mesh.triangles.push_back({startCentre, ring(0, j + 1), ring(0, j)});
    mesh.triangles.push_back({endCentre, ring(n - 1, j), ring(n - 1, j + 1)});
  }
  return mesh;
}

}  // namespace sdfccd
