/// @file
/// @brief buildSdf: exact distances per block of nodes with candidate triangles, then the sign (paper
/// Section 5, Table 1).
///
/// @details Distance pass, per block of up to 8^3 nodes (one task of parallelFor):
///  1. d_c = exact distance from the block centre c (BVH query); every node p of the block then has
///     d(p) <= d_c + r, r the block's half-diagonal.
///  2. Candidates: the triangles whose bounding box is within d_c + r of the block's box (BVH traversal).
///     Each gets the key k_t = distance from c to its box, a lower bound of d(c, t); candidates are sorted
///     by key into float SoA arrays (box corners rounded outward, so float bounds stay conservative).
///  3. Per node p (|p - c| = r_p), warm-started with the previous node's closest triangle: walk the
///     candidates in chunks of 16; stop when k_t - r_p > best (then d(p, t) >= k_t - r_p > best for all
///     remaining t); within a chunk the box lower bounds are computed branch-free (vectorized), and only
///     triangles whose box may beat the current best get the exact double closest-point test.
/// Sign pass: pseudonormal of the closest feature (closed meshes), or the fast winding number per node;
/// a block whose ball holds no surface and whose centre winding number is clearly 0 or 1 (|w - 1/2| >
/// 1/4) takes that sign for all its nodes (w is continuous off the surface and, on closed parts, constant).
#include "sdfccd/sdf_builder.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <sstream>

#include "mesh_pseudonormals.h"
#include "sdfccd/error.h"
#include "sdfccd/parallel_for.h"
#include "triangle_bvh.h"
#include "triangle_distance.h"
#include "winding_number.h"

namespace sdfccd {

using detail::FastWindingNumber;
using detail::MeshPseudonormals;
using detail::TriangleBvh;
using detail::TriangleFeature;

const char* toString(SdfSignMethod method) {
  switch (method) {
    case SdfSignMethod::Automatic: return "automatic";
    case SdfSignMethod::Pseudonormal: return "pseudonormal";
    case SdfSignMethod::WindingNumber: return "winding-number";
  }
  return "?";
}

bool isClosedAndOriented(const TriangleMesh& mesh) {
  // Every directed edge must occur once, and its reverse once.
  std::vector<std::uint64_t> directed;
  directed.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      directed.push_back(static_cast<std::uint64_t>(static_cast<std::uint32_t>(t[e])) << 32 |
                         static_cast<std::uint32_t>(t[(e + 1) % 3]));
    }
  }
  std::sort(directed.begin(), directed.end());
  if (std::adjacent_find(directed.begin(), directed.end()) != directed.end()) return false;
  for (const std::uint64_t key : directed) {
    const std::uint64_t reverse = (key << 32) | (key >> 32);
    if (!std::binary_search(directed.begin(), directed.end(), reverse)) return false;
  }
  return !directed.empty();
}

SdfGridLayout computeSdfGridLayout(const Box3& meshBounds, const SdfBuildSettings& settings) {
  if (settings.resolution < 1 || settings.resolution > 4096) {
    throw Error("resolution must be in 1..4096 cells, got " + std::to_string(settings.resolution));
  }
  if (settings.padding < 0 || settings.padding > 4096) {
    throw Error("padding must be in 0..4096 cells, got " + std::to_string(settings.padding));
  }
  if (meshBounds.isEmpty() || !meshBounds.min().allFinite() || !meshBounds.max().allFinite()) {
    throw Error("mesh bounds are empty or not finite");
  }
  const Vec3 extent = meshBounds.sizes();
  const double longest = extent.maxCoeff();
  if (!(longest > 0.0)) throw Error("mesh has zero extent (all vertices coincide)");
  SdfGridLayout layout;
  layout.spacing = longest / settings.resolution;
  const Vec3 centre = meshBounds.center();
  for (int a = 0; a < 3; ++a) {
    // The longest axis gets exactly `resolution` cells; the others the fewest that cover the mesh. The mesh
    // is centred in the grid.
    const double cellsExact = extent[a] / layout.spacing;
    long long cells = static_cast<long long>(std::ceil(cellsExact - 1e-9));
    cells = std::max(cells, 1LL) + 2LL * settings.padding;
    if (cells + 1 > 65536) throw Error("grid would have more than 65536 nodes along an axis");
    layout.nodeCounts[a] = static_cast<int>(cells + 1);
    layout.origin[a] = centre[a] - 0.5 * static_cast<double>(cells) * layout.spacing;
  }
  const double bytes = static_cast<double>(layout.nodeCounts.x()) * layout.nodeCounts.y() * layout.nodeCounts.z() * 4.0;
  if (bytes > static_cast<double>(settings.maxMemoryBytes)) {
    std::ostringstream s;
    s << "grid of " << layout.nodeCounts.x() << " x " << layout.nodeCounts.y() << " x " << layout.nodeCounts.z()
      << " nodes needs " << bytes / (1024.0 * 1024.0) << " MiB, over the limit of "
      << static_cast<double>(settings.maxMemoryBytes) / (1024.0 * 1024.0) << " MiB";
    throw Error(s.str());
  }
  return layout;
}

namespace {

constexpr int kBlock = 8;   // nodes per block side
constexpr int kChunk = 16;  // candidates per vectorized chunk

struct Block {
  Vec3i begin;  // first node
  Vec3i end;    // one past the last node
};

// Per-thread scratch, reused across blocks.
struct Scratch {
  std::vector<int> candidates;
  std::vector<std::pair<float, int>> sorted;
  std::vector<float> key, lox, loy, loz, hix, hiy, hiz;
  std::vector<int> position;
  std::size_t candidateTotal = 0;
};

struct Context {
  const TriangleBvh* bvh;
  const SdfGridLayout* layout;
  float slack;  // absolute float rounding allowance on lower bounds (model units)
};

float roundDown(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float roundUp(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// The distance pass of one block: writes |distance| to outDistance and the closest triangle position and
// feature per node (for the sign). Compiled for AVX2 and baseline; the loader picks at run time.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("avx2", "default")))
#endif
void distanceBlock(const Context& ctx, const Block& block, Scratch& s, float* outDistance, int* outPosition) {
  const TriangleBvh& bvh = *ctx.bvh;
  const SdfGridLayout& layout = *ctx.layout;
  const double h = layout.spacing;
  const Vec3 lo = layout.origin + h * block.begin.cast<double>();
  const Vec3 hi = layout.origin + h * (block.end - Vec3i::Ones()).cast<double>();
  const Vec3 centre = 0.5 * (lo + hi);
  const double radius = 0.5 * (hi - lo).norm();

  double centre2 = std::numeric_limits<double>::infinity();
  int centrePosition = -1;
  bvh.closest(centre, centre2, centrePosition);
  const double bound = (std::sqrt(centre2) + radius) * (1.0 + 1e-12) + 1e-300;

  s.candidates.clear();
  bvh.collectNearBox(lo, hi, bound, s.candidates);
  s.sorted.clear();
  for (const int q : s.candidates) {
    const double k = std::sqrt(TriangleBvh::squaredBoxDistance(centre, bvh.boxLo(q), bvh.boxHi(q)));
    s.sorted.emplace_back(roundDown(k) - ctx.slack, q);
  }
  std::sort(s.sorted.begin(), s.sorted.end(),
            [](const std::pair<float, int>& x, const std::pair<float, int>& y) { return x.first < y.first; });
  const std::size_t count = s.sorted.size();
  const std::size_t padded = (count + kChunk - 1) / kChunk * kChunk;
  for (auto* v : {&s.key, &s.lox, &s.loy, &s.loz, &s.hix, &s.hiy, &s.hiz}) v->resize(padded);
  s.position.resize(padded);
  const float inf = std::numeric_limits<float>::infinity();
  for (std::size_t m = 0; m < padded; ++m) {
    if (m < count) {
      const int q = s.sorted[m].second;
      s.key[m] = s.sorted[m].first;
      s.lox[m] = roundDown(bvh.boxLo(q).x());
      s.loy[m] = roundDown(bvh.boxLo(q).y());
      s.loz[m] = roundDown(bvh.boxLo(q).z());
      s.hix[m] = roundUp(bvh.boxHi(q).x());
      s.hiy[m] = roundUp(bvh.boxHi(q).y());
      s.hiz[m] = roundUp(bvh.boxHi(q).z());
      s.position[m] = q;
    } else {  // padding: a box at infinity never passes
      s.key[m] = inf;
      s.lox[m] = s.loy[m] = s.loz[m] = inf;
      s.hix[m] = s.hiy[m] = s.hiz[m] = inf;
      s.position[m] = -1;
    }
  }
  s.candidateTotal += count;

  const float* key = s.key.data();
  const float* lox = s.lox.data();
  const float* loy = s.loy.data();
  const float* loz = s.loz.data();
  const float* hix = s.hix.data();
  const float* hiy = s.hiy.data();
  const float* hiz = s.hiz.data();
  int previous = centrePosition;
  const Vec3i n = layout.nodeCounts;
  for (int k = block.begin.z(); k < block.end.z(); ++k) {
    for (int j = block.begin.y(); j < block.end.y(); ++j) {
      for (int i = block.begin.x(); i < block.end.x(); ++i) {
        const Vec3 p = layout.origin + h * Vec3(i, j, k);
        const float rp = roundUp((p - centre).norm());
        double best2 = bvh.squaredDistance(p, previous);
        int bestPosition = previous;
        float bestF = roundUp(std::sqrt(best2));
        float threshold = (bestF + ctx.slack) * (bestF + ctx.slack);
        const float px = static_cast<float>(p.x()), py = static_cast<float>(p.y()), pz = static_cast<float>(p.z());
        for (std::size_t c = 0; c < padded; c += kChunk) {
          if (key[c] - rp > bestF) break;
          float d2[kChunk];
          for (int m = 0; m < kChunk; ++m) {
            const float gx = std::max(std::max(lox[c + m] - px, px - hix[c + m]), 0.0f);
            const float gy = std::max(std::max(loy[c + m] - py, py - hiy[c + m]), 0.0f);
            const float gz = std::max(std::max(loz[c + m] - pz, pz - hiz[c + m]), 0.0f);
            d2[m] = gx * gx + gy * gy + gz * gz;
          }
          for (int m = 0; m < kChunk; ++m) {
            if (!(d2[m] <= threshold)) continue;
            const int q = s.position[c + m];
            if (q == bestPosition) continue;
            const double e2 = bvh.squaredDistance(p, q);
            if (e2 < best2) {
              best2 = e2;
              bestPosition = q;
              bestF = roundUp(std::sqrt(best2));
              threshold = (bestF + ctx.slack) * (bestF + ctx.slack);
            }
          }
        }
        const std::size_t index = static_cast<std::size_t>(i) +
                                  static_cast<std::size_t>(n.x()) *
                                      (static_cast<std::size_t>(j) + static_cast<std::size_t>(n.y()) * static_cast<std::size_t>(k));
        outDistance[index] = static_cast<float>(std::sqrt(best2));
        outPosition[index] = bestPosition;
        previous = bestPosition;
      }
    }
  }
}

std::vector<Block> makeBlocks(const Vec3i& nodes) {
  std::vector<Block> blocks;
  for (int k = 0; k < nodes.z(); k += kBlock)
    for (int j = 0; j < nodes.y(); j += kBlock)
      for (int i = 0; i < nodes.x(); i += kBlock) {
        const Vec3i begin(i, j, k);
        blocks.push_back({begin, (begin + Vec3i::Constant(kBlock)).cwiseMin(nodes)});
      }
  return blocks;
}

// Calls `progress` (never concurrently, at most every 1/200 of the work) from whichever thread gets there.
class ProgressReporter {
 public:
  ProgressReporter(const ProgressCallback& progress, std::size_t total, double begin, double end)
      : m_progress(progress), m_total(std::max<std::size_t>(total, 1)), m_begin(begin), m_end(end) {}
  void advance() {
    const std::size_t done = ++m_done;
    if (!m_progress || (done * 200 / m_total == (done - 1) * 200 / m_total && done != m_total)) return;
    std::unique_lock<std::mutex> lock(m_mutex, std::try_to_lock);
    if (!lock.owns_lock()) return;
    m_progress(m_begin + (m_end - m_begin) * static_cast<double>(done) / static_cast<double>(m_total));
  }

 private:
  const ProgressCallback& m_progress;
  std::size_t m_total;
  double m_begin, m_end;
  std::atomic<std::size_t> m_done{0};
  std::mutex m_mutex;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

SdfBuildResult buildSdf(const TriangleMesh& mesh, const SdfBuildSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  if (mesh.vertices.empty() || mesh.triangles.empty()) throw Error("cannot build an SDF of an empty mesh");
  for (const Vec3& v : mesh.vertices) {
    if (!v.allFinite()) throw Error("cannot build an SDF: the mesh has non-finite vertices");
  }
  const int vertexCount = static_cast<int>(mesh.vertices.size());
  for (const auto& t : mesh.triangles) {
    for (int c : t) {
      if (c < 0 || c >= vertexCount) throw Error("cannot build an SDF: a face index is out of range");
    }
  }
  if (!(settings.windingAccuracy > 1.0) || !std::isfinite(settings.windingAccuracy)) {
    throw Error("winding accuracy (beta) must be finite and > 1");
  }
  const SdfGridLayout layout = computeSdfGridLayout(mesh.bounds(), settings);
  const int threads = settings.threads > 0 ? settings.threads : defaultThreadCount();

  SdfBuildResult result;
  SdfBuildStats& stats = result.stats;
  stats.threads = threads;
  stats.triangles = mesh.triangles.size();
  stats.signMethod = settings.signMethod;
  if (stats.signMethod == SdfSignMethod::Automatic) {
    stats.signMethod = isClosedAndOriented(mesh) ? SdfSignMethod::Pseudonormal : SdfSignMethod::WindingNumber;
  }

  const TriangleBvh bvh(mesh);
  double largest = 0.0;
  for (int a = 0; a < 3; ++a) {
    largest = std::max({largest, std::fabs(layout.origin[a]),
                        std::fabs(layout.origin[a] + layout.spacing * (layout.nodeCounts[a] - 1))});
  }
  for (const Vec3& v : mesh.vertices) largest = std::max(largest, v.cwiseAbs().maxCoeff());
  Context ctx{&bvh, &layout, static_cast<float>(16.0 * std::numeric_limits<float>::epsilon() * largest)};

  const std::size_t nodeCount = layout.nodeCount();
  std::vector<float> values(nodeCount);
  std::vector<int> closestPosition(nodeCount);
  const std::vector<Block> blocks = makeBlocks(layout.nodeCounts);
  std::vector<Scratch> scratch(static_cast<std::size_t>(threads));
  const bool winding = stats.signMethod == SdfSignMethod::WindingNumber;
  ProgressReporter distanceProgress(settings.progress, blocks.size(), 0.0, winding ? 0.7 : 1.0);
  parallelFor(blocks.size(), threads, [&](std::size_t b, int thread) {
    distanceBlock(ctx, blocks[b], scratch[static_cast<std::size_t>(thread)], values.data(), closestPosition.data());
    distanceProgress.advance();
  });
  stats.distanceSeconds = secondsSince(start);
  std::size_t scratchBytes = 0;
  std::size_t candidateTotal = 0;
  for (const Scratch& s : scratch) {
    candidateTotal += s.candidateTotal;
    scratchBytes += s.candidates.capacity() * sizeof(int) + s.sorted.capacity() * sizeof(s.sorted[0]) +
                    8 * s.key.capacity() * sizeof(float);
  }
  stats.meanCandidates = static_cast<double>(candidateTotal) / static_cast<double>(std::max<std::size_t>(blocks.size(), 1));

  const auto signStart = std::chrono::steady_clock::now();
  std::size_t signBytes = 0;
  const Vec3i n = layout.nodeCounts;
  auto nodePosition = [&](int i, int j, int k) { return Vec3(layout.origin + layout.spacing * Vec3(i, j, k)); };
  if (!winding) {
    const MeshPseudonormals normals(mesh);
    signBytes = normals.memoryBytes();
    ProgressReporter signProgress(ProgressCallback(), blocks.size(), 0.0, 1.0);
    parallelFor(blocks.size(), threads, [&](std::size_t b, int) {
      const Block& block = blocks[b];
      for (int k = block.begin.z(); k < block.end.z(); ++k)
        for (int j = block.begin.y(); j < block.end.y(); ++j)
          for (int i = block.begin.x(); i < block.end.x(); ++i) {
            const std::size_t index = static_cast<std::size_t>(i) + static_cast<std::size_t>(n.x()) *
                                      (static_cast<std::size_t>(j) + static_cast<std::size_t>(n.y()) * static_cast<std::size_t>(k));
            const int q = closestPosition[index];
            const Vec3 p = nodePosition(i, j, k);
            Vec3 closest;
            TriangleFeature feature;
            detail::closestPointOnTriangle(p, bvh.a(q), bvh.b(q), bvh.c(q), closest, feature);
            if ((p - closest).dot(normals.normal(bvh.triangleIndex(q), feature)) < 0.0) values[index] = -values[index];
          }
    });
  } else {
    const FastWindingNumber windingNumber(bvh, settings.windingAccuracy);
    signBytes = windingNumber.memoryBytes();
    const double threshold = settings.windingThreshold;
    ProgressReporter signProgress(settings.progress, blocks.size(), 0.7, 1.0);
    parallelFor(blocks.size(), threads, [&](std::size_t b, int) {
      const Block& block = blocks[b];
      const Vec3 lo = nodePosition(block.begin.x(), block.begin.y(), block.begin.z());
      const Vec3 hi = nodePosition(block.end.x() - 1, block.end.y() - 1, block.end.z() - 1);
      const Vec3 centre = 0.5 * (lo + hi);
      const double radius = 0.5 * (hi - lo).norm();
      double centre2 = std::numeric_limits<double>::infinity();
      int centrePosition = -1;
      bvh.closest(centre, centre2, centrePosition);
      int uniformSign = 0;  // 0: decide per node
      if (std::sqrt(centre2) > radius * 1.01) {
        const double w = windingNumber(centre);
        if (std::fabs(w - 0.5) > 0.25) uniformSign = w >= threshold ? -1 : 1;
      }
      for (int k = block.begin.z(); k < block.end.z(); ++k)
        for (int j = block.begin.y(); j < block.end.y(); ++j)
          for (int i = block.begin.x(); i < block.end.x(); ++i) {
            const std::size_t index = static_cast<std::size_t>(i) + static_cast<std::size_t>(n.x()) *
                                      (static_cast<std::size_t>(j) + static_cast<std::size_t>(n.y()) * static_cast<std::size_t>(k));
            const bool inside = uniformSign != 0 ? uniformSign < 0 : windingNumber(nodePosition(i, j, k)) >= threshold;
            if (inside) values[index] = -values[index];
          }
      signProgress.advance();
    });
  }
  stats.signSeconds = secondsSince(signStart);
  closestPosition.clear();
  closestPosition.shrink_to_fit();

  result.grid = std::make_shared<const SdfGrid>(layout.nodeCounts, layout.origin, layout.spacing, std::move(values));
  stats.gridBytes = result.grid->memoryBytes();
  stats.peakExtraBytes = bvh.memoryBytes() + nodeCount * sizeof(int) + scratchBytes + signBytes;
  stats.seconds = secondsSince(start);
  if (settings.progress) settings.progress(1.0);
  return result;
}

}  // namespace sdfccd
