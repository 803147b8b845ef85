/// @file
/// @brief The sign of buildSdf: the winding-number pass and the checks of the pseudonormal sign (sdf_sign.h).
#include "sdf_sign.h"

#include <atomic>
#include <cmath>
#include <limits>

#include "sdfccd/parallel_for.h"

namespace sdfccd::detail {

namespace {

double orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).cross(c - a).dot(d - a);
}

// True when segment pq passes strictly through the interior of triangle abc: p and q strictly on opposite
// sides of its plane, and the line pq strictly inside its three edges. Rounding can only misjudge nearly
// touching cases, and a false "crossing" only costs the (always right) winding-number sign.
bool segmentCrossesTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double op = orient(a, b, c, p), oq = orient(a, b, c, q);
  if (!((op > 0.0 && oq < 0.0) || (op < 0.0 && oq > 0.0))) return false;
  const double s1 = orient(p, q, a, b), s2 = orient(p, q, b, c), s3 = orient(p, q, c, a);
  return (s1 > 0.0 && s2 > 0.0 && s3 > 0.0) || (s1 < 0.0 && s2 < 0.0 && s3 < 0.0);
}

bool trianglesCross(const Vec3 t[3], const Vec3 u[3]) {
  for (int e = 0; e < 3; ++e) {
    if (segmentCrossesTriangle(t[e], t[(e + 1) % 3], u[0], u[1], u[2])) return true;
    if (segmentCrossesTriangle(u[e], u[(e + 1) % 3], t[0], t[1], t[2])) return true;
  }
  return false;
}

bool shareVertex(const std::array<int, 3>& s, const std::array<int, 3>& t) {
  for (int i = 0; i < 3; ++i) {
    if (s[i] == t[0] || s[i] == t[1] || s[i] == t[2]) return true;
  }
  return false;
}

// The block's corner nodes, centre and half-diagonal, in model units.
struct BlockBall {
  Vec3 centre;
  double radius;
};

BlockBall blockBall(const SdfGridLayout& layout, const Block& block) {
  const Vec3 lo = layout.origin + layout.spacing * block.begin.cast<double>();
  const Vec3 hi = layout.origin + layout.spacing * (block.end - Vec3i::Ones()).cast<double>();
  return {0.5 * (lo + hi), 0.5 * (hi - lo).norm()};
}

// -1 (inside) or +1 (outside) when the block's ball holds no surface and its centre's winding number is
// clearly 0 or 1: the sign of every node of the block (w is continuous off the surface). 0: undecided.
int uniformBlockSign(const TriangleBvh& bvh, const FastWindingNumber& winding, double threshold,
                     const BlockBall& ball) {
  double centre2 = std::numeric_limits<double>::infinity();
  int centrePosition = -1;
  bvh.closest(ball.centre, centre2, centrePosition);
  if (!(std::sqrt(centre2) > ball.radius * 1.01)) return 0;
  const double w = winding(ball.centre);
  if (!(std::fabs(w - 0.5) > 0.25)) return 0;
  return w >= threshold ? -1 : 1;
}

}  // namespace

std::size_t countSelfIntersections(const TriangleMesh& mesh, const TriangleBvh& bvh, int threads) {
  std::atomic<std::size_t> pairs{0};
  const std::size_t count = bvh.size();
  constexpr std::size_t kTask = 256;  // triangle positions per parallel task
  std::vector<std::vector<int>> found(static_cast<std::size_t>(std::max(threads, 1)));
  parallelFor((count + kTask - 1) / kTask, threads, [&](std::size_t task, int thread) {
    std::vector<int>& near = found[static_cast<std::size_t>(thread)];
    std::size_t local = 0;
    for (std::size_t q = task * kTask; q < std::min(count, (task + 1) * kTask); ++q) {
      const int i = static_cast<int>(q);
      const Vec3 t[3] = {bvh.a(i), bvh.b(i), bvh.c(i)};
      const auto& ti = mesh.triangles[static_cast<std::size_t>(bvh.triangleIndex(i))];
      near.clear();
      bvh.collectNearBox(bvh.boxLo(i), bvh.boxHi(i), 0.0, near);
      for (const int j : near) {
        if (j <= i) continue;  // each pair once
        const auto& tj = mesh.triangles[static_cast<std::size_t>(bvh.triangleIndex(j))];
        if (shareVertex(ti, tj)) continue;  // neighbours meet along their shared vertex or edge
        const Vec3 u[3] = {bvh.a(j), bvh.b(j), bvh.c(j)};
        if (trianglesCross(t, u)) ++local;
      }
    }
    pairs += local;
  });
  return pairs.load();
}

std::size_t countSignsDisagreeingWithWinding(const TriangleBvh& bvh, const FastWindingNumber& winding,
                                             const SdfGridLayout& layout, const std::vector<Block>& blocks, int threads,
                                             const float* values) {
  std::atomic<std::size_t> disagreeing{0};
  parallelFor(blocks.size(), threads, [&](std::size_t b, int) {
    const Block& block = blocks[b];
    const int sign = uniformBlockSign(bvh, winding, 0.5, blockBall(layout, block));
    if (sign == 0) return;
    std::size_t local = 0;
    for (int k = block.begin.z(); k < block.end.z(); ++k)
      for (int j = block.begin.y(); j < block.end.y(); ++j)
        for (int i = block.begin.x(); i < block.end.x(); ++i) {
          const bool inside = values[nodeIndex(layout.nodeCounts, i, j, k)] < 0.0f;
          if (inside != (sign < 0)) ++local;
        }
    disagreeing += local;
  });
  return disagreeing.load();
}

void signByWindingNumber(const TriangleBvh& bvh, const FastWindingNumber& winding, double threshold,
                         const SdfGridLayout& layout, const std::vector<Block>& blocks, int threads,
                         ProgressReporter& progress, float* values) {
  parallelFor(blocks.size(), threads, [&](std::size_t b, int) {
    const Block& block = blocks[b];
    const int uniformSign = uniformBlockSign(bvh, winding, threshold, blockBall(layout, block));
    for (int k = block.begin.z(); k < block.end.z(); ++k)
      for (int j = block.begin.y(); j < block.end.y(); ++j)
        for (int i = block.begin.x(); i < block.end.x(); ++i) {
          float& value = values[nodeIndex(layout.nodeCounts, i, j, k)];
          const Vec3 p = layout.origin + layout.spacing * Vec3(i, j, k);
          const bool inside = uniformSign != 0 ? uniformSign < 0 : winding(p) >= threshold;
          if (inside) value = -value;
        }
    progress.advance();
  });
}

}  // namespace sdfccd::detail
