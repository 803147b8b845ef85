/// @file
/// @brief TriangleBvh: construction and the closest-point and box-range queries.
#include "triangle_bvh.h"

#include <algorithm>
#include <numeric>

#include "triangle_distance.h"

namespace sdfccd::detail {

namespace {
constexpr int kLeafSize = 4;
}

TriangleBvh::TriangleBvh(const TriangleMesh& mesh) {
  const int n = static_cast<int>(mesh.triangles.size());
  m_order.resize(static_cast<std::size_t>(n));
  std::iota(m_order.begin(), m_order.end(), 0);
  std::vector<Vec3> centroids(static_cast<std::size_t>(n));
  for (int t = 0; t < n; ++t) {
    const auto& tri = mesh.triangles[t];
    centroids[t] = (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
  }
  m_a.resize(static_cast<std::size_t>(n));
  m_b.resize(static_cast<std::size_t>(n));
  m_c.resize(static_cast<std::size_t>(n));
  m_boxLo.resize(static_cast<std::size_t>(n));
  m_boxHi.resize(static_cast<std::size_t>(n));
  m_nodes.reserve(static_cast<std::size_t>(2 * n / kLeafSize + 2));
  // Fill positions first (build() sorts m_order ranges and reads the boxes).
  std::vector<Vec3> triLo(static_cast<std::size_t>(n)), triHi(static_cast<std::size_t>(n));
  for (int t = 0; t < n; ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3& a = mesh.vertices[tri[0]];
    const Vec3& b = mesh.vertices[tri[1]];
    const Vec3& c = mesh.vertices[tri[2]];
    triLo[t] = a.cwiseMin(b).cwiseMin(c);
    triHi[t] = a.cwiseMax(b).cwiseMax(c);
  }
  m_boxLo = triLo;
  m_boxHi = triHi;
  build(0, n, centroids);
  for (int p = 0; p < n; ++p) {
    const int t = m_order[p];
    const auto& tri = mesh.triangles[t];
    m_a[p] = mesh.vertices[tri[0]];
    m_b[p] = mesh.vertices[tri[1]];
    m_c[p] = mesh.vertices[tri[2]];
    m_boxLo[p] = triLo[t];
    m_boxHi[p] = triHi[t];
  }
}

int TriangleBvh::build(int start, int count, std::vector<Vec3>& centroids) {
  const int index = static_cast<int>(m_nodes.size());
  m_nodes.emplace_back();
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  Vec3 cLo = lo, cHi = hi;
  for (int p = start; p < start + count; ++p) {
    const int t = m_order[p];
    lo = lo.cwiseMin(m_boxLo[t]);
    hi = hi.cwiseMax(m_boxHi[t]);
    cLo = cLo.cwiseMin(centroids[t]);
    cHi = cHi.cwiseMax(centroids[t]);
  }
  m_nodes[index].lo = lo;
  m_nodes[index].hi = hi;
  m_nodes[index].start = start;
  m_nodes[index].count = count;
  if (count <= kLeafSize) return index;
  int axis = 0;
  (cHi - cLo).maxCoeff(&axis);
  const int half = count / 2;
  std::nth_element(m_order.begin() + start, m_order.begin() + start + half, m_order.begin() + start + count,
                   [&](int x, int y) { return centroids[x][axis] < centroids[y][axis]; });
  build(start, half, centroids);
  const int right = build(start + half, count - half, centroids);
  m_nodes[index].right = right;
  return index;
}

double TriangleBvh::squaredDistance(const Vec3& p, int position) const {
  return squaredDistanceToTriangle(p, m_a[position], m_b[position], m_c[position]);
}

void TriangleBvh::closest(const Vec3& p, double& ioBest2, int& ioPosition) const {
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = m_nodes[stack[--top]];
    if (squaredBoxDistance(p, node.lo, node.hi) >= ioBest2) continue;
    if (node.right < 0) {
      for (int q = node.start; q < node.start + node.count; ++q) {
        if (squaredBoxDistance(p, m_boxLo[q], m_boxHi[q]) >= ioBest2) continue;
        const double d2 = squaredDistance(p, q);
        if (d2 < ioBest2) {
          ioBest2 = d2;
          ioPosition = q;
        }
      }
      continue;
    }
    const int left = static_cast<int>(&node - m_nodes.data()) + 1;
    const double dl = squaredBoxDistance(p, m_nodes[left].lo, m_nodes[left].hi);
    const double dr = squaredBoxDistance(p, m_nodes[node.right].lo, m_nodes[node.right].hi);
    // Push the farther child first so the nearer one is searched first and tightens the bound.
    if (dl < dr) {
      if (dr < ioBest2) stack[top++] = node.right;
      if (dl < ioBest2) stack[top++] = left;
    } else {
      if (dl < ioBest2) stack[top++] = left;
      if (dr < ioBest2) stack[top++] = node.right;
    }
  }
}

void TriangleBvh::collectNearBox(const Vec3& lo, const Vec3& hi, double radius, std::vector<int>& out) const {
  const double r2 = radius * radius;
  auto boxBox2 = [&](const Vec3& l, const Vec3& h) {
    const Vec3 gap = (l - hi).cwiseMax(lo - h).cwiseMax(0.0);
    return gap.squaredNorm();
  };
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = m_nodes[stack[--top]];
    if (boxBox2(node.lo, node.hi) > r2) continue;
    if (node.right < 0) {
      for (int q = node.start; q < node.start + node.count; ++q) {
        if (boxBox2(m_boxLo[q], m_boxHi[q]) <= r2) out.push_back(q);
      }
      continue;
    }
    stack[top++] = node.right;
    stack[top++] = static_cast<int>(&node - m_nodes.data()) + 1;
  }
}

std::size_t TriangleBvh::memoryBytes() const {
  return m_nodes.capacity() * sizeof(Node) + m_order.capacity() * sizeof(int) + 5 * m_a.capacity() * sizeof(Vec3);
}

}  // namespace sdfccd::detail
