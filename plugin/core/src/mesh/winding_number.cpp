/// @file
/// @brief FastWindingNumber: cluster dipoles bottom-up, then a far-field/near-field traversal per query.
#include "winding_number.h"

#include <algorithm>
#include <cmath>

namespace sdfccd::detail {

namespace {
constexpr double kInvFourPi = 0.25 / 3.14159265358979323846;
}

FastWindingNumber::FastWindingNumber(const TriangleBvh& bvh, double beta) : m_bvh(bvh) {
  const auto& nodes = bvh.nodes();
  m_clusters.resize(nodes.size());
  // Subtrees cover contiguous triangle positions, so each cluster is a direct sum over its range; the
  // total work is O(n log n), negligible next to the grid.
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const auto& node = nodes[n];
    Vec3 areaVector = Vec3::Zero();
    Vec3 weighted = Vec3::Zero();
    double area = 0.0;
    for (int q = node.start; q < node.start + node.count; ++q) {
      const Vec3 av = 0.5 * (bvh.b(q) - bvh.a(q)).cross(bvh.c(q) - bvh.a(q));
      const double a = av.norm();
      areaVector += av;
      weighted += a * (bvh.a(q) + bvh.b(q) + bvh.c(q)) / 3.0;
      area += a;
    }
    const Vec3 centre = area > 0.0 ? Vec3(weighted / area) : Vec3(0.5 * (node.lo + node.hi));
    double r2 = 0.0;
    for (int q = node.start; q < node.start + node.count; ++q) {
      r2 = std::max({r2, (bvh.a(q) - centre).squaredNorm(), (bvh.b(q) - centre).squaredNorm(),
                     (bvh.c(q) - centre).squaredNorm()});
    }
    m_clusters[n] = {centre, areaVector, beta * beta * r2};
  }
}

double FastWindingNumber::triangleWinding(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 x = a - p, y = b - p, z = c - p;
  const double lx = x.norm(), ly = y.norm(), lz = z.norm();
  const double numerator = x.dot(y.cross(z));
  const double denominator = lx * ly * lz + x.dot(y) * lz + y.dot(z) * lx + z.dot(x) * ly;
  return 2.0 * std::atan2(numerator, denominator) * kInvFourPi;
}

double FastWindingNumber::operator()(const Vec3& p) const {
  const auto& nodes = m_bvh.nodes();
  double w = 0.0;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const int n = stack[--top];
    const Cluster& cluster = m_clusters[n];
    const Vec3 d = cluster.centre - p;
    const double d2 = d.squaredNorm();
    if (d2 > cluster.radius2) {
      w += cluster.areaVector.dot(d) / (d2 * std::sqrt(d2)) * kInvFourPi;
      continue;
    }
    const auto& node = nodes[n];
    if (node.right < 0) {
      for (int q = node.start; q < node.start + node.count; ++q) {
        w += triangleWinding(p, m_bvh.a(q), m_bvh.b(q), m_bvh.c(q));
      }
      continue;
    }
    stack[top++] = node.right;
    stack[top++] = n + 1;
  }
  return w;
}

}  // namespace sdfccd::detail
