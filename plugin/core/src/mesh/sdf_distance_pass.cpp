/// @file
/// @brief The distance pass of buildSdf: exact distances per block of nodes with candidate triangles (paper
/// Section 5, Table 1).
///
/// @details The grid is cut into blocks of up to 8^3 nodes, one parallel task each, and each
/// block is refined like an octree (8 -> 4 -> 2 nodes per side). A box of nodes with centre c and
/// half-diagonal r keeps a candidate list: the triangles whose bounding box lies within d(c) + r of the box,
/// d(c) the exact distance from c. Every node p of the box has d(p) <= d(c) + r, so its closest triangle is
/// in the list. The block's list comes from the BVH; each child's list is filtered from its parent's (its
/// d(c) found within the parent's list), so lists shrink with the box. At 2^3 nodes, every node finds its
/// exact closest triangle in the list in three stages of increasing cost and decreasing count:
///  1. float box lower bounds of all candidates (SoA, eight at a time), keeping those below the current best
///     (warm start: the previous node's closest triangle, whose exact distance is an upper bound);
///  2. a float point-triangle distance of the survivors (branch-free, eight at a time) that never exceeds
///     the true distance by more than the float rounding allowance;
///  3. the exact double closest point (Ericson) by increasing float estimate, until the estimate exceeds
///     the best exact distance.
/// Float bounds stay conservative: boxes are rounded outward and every comparison carries an allowance
/// for float rounding, so the result equals the brute-force minimum over all triangles.
/// With pseudonormals (closed meshes) each node is signed right here by the closest feature's pseudonormal.
#include "sdf_distance_pass.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "sdfccd/parallel_for.h"
#include "sdfccd/tolerances.h"
#include "triangle_distance.h"

namespace sdfccd::detail {

namespace {

constexpr int kChunk = 16;  // candidates per vectorized chunk
constexpr int kLevels = 3;  // candidate lists for boxes of 8, 4 and 2 nodes per side

float roundDown(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float roundUp(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// Candidate triangles as float SoA boxes (rounded outward) plus their BVH positions, padded with boxes at
// infinity to a multiple of kChunk so that chunk loops need no tail. Arrays only grow (reused per thread).
struct CandidateList {
  std::vector<float> lox, loy, loz, hix, hiy, hiz;
  std::vector<int> position;
  std::size_t size = 0;    // real entries
  std::size_t padded = 0;  // entries including the padding

  void reserve(std::size_t n) {
    if (position.size() >= n) return;
    for (auto* v : {&lox, &loy, &loz, &hix, &hiy, &hiz}) v->resize(2 * n);
    position.resize(2 * n);
  }
  void clear() { size = padded = 0; }
  void push(float x0, float y0, float z0, float x1, float y1, float z1, int q) {
    reserve(size + 1);
    lox[size] = x0, loy[size] = y0, loz[size] = z0, hix[size] = x1, hiy[size] = y1, hiz[size] = z1;
    position[size] = q;
    ++size;
  }
  void pad() {
    const float inf = std::numeric_limits<float>::infinity();
    padded = (size + kChunk - 1) / kChunk * kChunk;
    reserve(padded);
    for (std::size_t m = size; m < padded; ++m) {
      lox[m] = loy[m] = loz[m] = hix[m] = hiy[m] = hiz[m] = inf;
      position[m] = -1;
    }
  }
  std::size_t bytes() const { return position.capacity() * (sizeof(int) + 6 * sizeof(float)); }
};

// The triangles in BVH order as float records of one cache line each (corners, unit normal, inverse squared
// edge lengths), for the vectorized distance screen of closestInList(): a survivor costs one line to fetch.
struct TriangleRecords {
  static constexpr int kFields = 16;  // 15 used, 1 padding
  std::vector<float> data;            // kFields floats per BVH position

  explicit TriangleRecords(const TriangleBvh& bvh) : data(bvh.size() * kFields, 0.0f) {
    for (std::size_t q = 0; q < bvh.size(); ++q) {
      const int i = static_cast<int>(q);
      const Vec3 &a = bvh.a(i), &b = bvh.b(i), &c = bvh.c(i);
      const Vec3 normal = (b - a).cross(c - a).normalized();
      const double fields[15] = {a.x(),
                                 a.y(),
                                 a.z(),
                                 b.x(),
                                 b.y(),
                                 b.z(),
                                 c.x(),
                                 c.y(),
                                 c.z(),
                                 normal.x(),
                                 normal.y(),
                                 normal.z(),
                                 1.0 / (b - a).squaredNorm(),
                                 1.0 / (c - b).squaredNorm(),
                                 1.0 / (a - c).squaredNorm()};
      for (int f = 0; f < 15; ++f) data[q * kFields + f] = static_cast<float>(fields[f]);
    }
  }
  std::size_t bytes() const { return data.capacity() * sizeof(float); }
};

// Float screen buffers of one closestInList() call: survivor indices, and the survivors' triangles in SoA
// batches of kBatch lanes at fixed offsets (so the gather's stores need no per-field pointer).
constexpr std::size_t kBatch = 256;
struct ScreenBuffers {
  std::vector<int> position;
  alignas(32) float lane[16][kBatch];  // fields as in TriangleRecords, then the estimates (lane[15])
  void reserve(std::size_t n) {
    if (position.size() < n) position.resize(2 * n);
  }
};

// Per-thread scratch, reused across blocks.
struct Scratch {
  std::vector<int> bvhCandidates;
  CandidateList level[kLevels];
  ScreenBuffers screen;
  std::size_t candidateTotal = 0;
};

struct Context {
  const TriangleBvh* bvh;
  const TriangleRecords* records;
  const SdfGridLayout* layout;
  const MeshPseudonormals* normals;  // null: leave the distance unsigned (the winding pass signs it)
  float slack;                       // absolute float rounding allowance on lower bounds (model units)
  float areaTolerance;               // float rounding allowance of the inside test (model units^2)
};

// Eight floats processed together: GCC/Clang vector extensions (lowered to AVX where the function is
// compiled for it, to SSE pairs otherwise). Written by hand because GCC 12 at -O2 does not vectorize these
// loops on its own.
#if defined(__clang__)
#pragma clang diagnostic ignored "-Wpsabi"  // Vec8f never crosses a call: every helper is always inlined
#elif defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"  // Vec8f never crosses a call: every helper is always inlined
#endif
typedef float Vec8f __attribute__((vector_size(32)));
// The two hot functions are compiled twice, for x86-64-v3 (AVX2, FMA) and for the baseline, and the dynamic loader
// picks one at start-up (GCC function multi-versioning): twice the speed on AVX2 machines, still portable.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__) && \
    !defined(__SANITIZE_THREAD__)
#define SDFCCD_HOT __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define SDFCCD_HOT
#endif
#define SDFCCD_INLINE inline __attribute__((always_inline))

SDFCCD_INLINE Vec8f load8(const float* p) {
  Vec8f v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}
SDFCCD_INLINE void store8(float* p, Vec8f v) {
  std::memcpy(p, &v, sizeof(v));
}
SDFCCD_INLINE Vec8f max8(Vec8f a, Vec8f b) {
  return a > b ? a : b;
}
SDFCCD_INLINE Vec8f min8(Vec8f a, Vec8f b) {
  return a < b ? a : b;
}
SDFCCD_INLINE Vec8f splat8(float x) {
  return Vec8f{x, x, x, x, x, x, x, x};
}
typedef int Vec8i __attribute__((vector_size(32)));
// True when any of the 2 x 8 squared bounds is <= limit: lets chunk loops skip their scalar compaction.
SDFCCD_INLINE bool anyAtMost(const float* d2, float limit) {
  const Vec8i m = (load8(d2) <= splat8(limit)) | (load8(d2 + 8) <= splat8(limit));
  return (m[0] | m[1] | m[2] | m[3] | m[4] | m[5] | m[6] | m[7]) != 0;
}

// Squared lower bounds (float) from point (px, py, pz) to the boxes of chunk [c, c + kChunk).
SDFCCD_INLINE void chunkPointBox(const CandidateList& l, std::size_t c, float px, float py, float pz, float* d2) {
  const Vec8f x = splat8(px), y = splat8(py), z = splat8(pz), zero = splat8(0.0f);
  for (int m = 0; m < kChunk; m += 8) {
    const Vec8f gx = max8(max8(load8(&l.lox[c + m]) - x, x - load8(&l.hix[c + m])), zero);
    const Vec8f gy = max8(max8(load8(&l.loy[c + m]) - y, y - load8(&l.hiy[c + m])), zero);
    const Vec8f gz = max8(max8(load8(&l.loz[c + m]) - z, z - load8(&l.hiz[c + m])), zero);
    store8(d2 + m, gx * gx + gy * gy + gz * gz);
  }
}

// Squared distance from (px, py, pz) to segments u + t (v - u), t in [0, 1], eight at once, in float.
SDFCCD_INLINE Vec8f segmentDistance2(Vec8f px, Vec8f py, Vec8f pz, Vec8f ux, Vec8f uy, Vec8f uz, Vec8f vx, Vec8f vy,
                                     Vec8f vz, Vec8f invLength2) {
  const Vec8f ex = vx - ux, ey = vy - uy, ez = vz - uz;
  const Vec8f wx = px - ux, wy = py - uy, wz = pz - uz;
  const Vec8f t = min8(max8((wx * ex + wy * ey + wz * ez) * invLength2, splat8(0.0f)), splat8(1.0f));
  const Vec8f dx = wx - t * ex, dy = wy - t * ey, dz = wz - t * ez;
  return dx * dx + dy * dy + dz * dz;
}

// Float screen: for survivors [0, count) of `b` (padded to a multiple of 8), a value that is at most the
// true squared distance plus float rounding: the squared plane distance when the projection may fall
// inside the triangle (the test is loosened by `tolerance`; the plane distance never exceeds the true
// one), otherwise the smallest squared distance to the three edges (the true one). Branch-free.
SDFCCD_INLINE void screenSurvivors(ScreenBuffers& b, std::size_t count, float pxs, float pys, float pzs,
                                   float tolerance) {
  const Vec8f px = splat8(pxs), py = splat8(pys), pz = splat8(pzs), tol = splat8(-tolerance);
  for (std::size_t m = 0; m < count; m += 8) {
    const Vec8f ax = load8(&b.lane[0][m]), ay = load8(&b.lane[1][m]), az = load8(&b.lane[2][m]);
    const Vec8f bx = load8(&b.lane[3][m]), by = load8(&b.lane[4][m]), bz = load8(&b.lane[5][m]);
    const Vec8f cx = load8(&b.lane[6][m]), cy = load8(&b.lane[7][m]), cz = load8(&b.lane[8][m]);
    const Vec8f nx = load8(&b.lane[9][m]), ny = load8(&b.lane[10][m]), nz = load8(&b.lane[11][m]);
    const Vec8f apx = px - ax, apy = py - ay, apz = pz - az;
    const Vec8f bpx = px - bx, bpy = py - by, bpz = pz - bz;
    const Vec8f cpx = px - cx, cpy = py - cy, cpz = pz - cz;
    const Vec8f abx = bx - ax, aby = by - ay, abz = bz - az;
    const Vec8f bcx = cx - bx, bcy = cy - by, bcz = cz - bz;
    const Vec8f cax = ax - cx, cay = ay - cy, caz = az - cz;
    // Signed areas of the projection against each edge, in the triangle's unit-normal frame.
    const Vec8f sa = nx * (aby * apz - abz * apy) + ny * (abz * apx - abx * apz) + nz * (abx * apy - aby * apx);
    const Vec8f sb = nx * (bcy * bpz - bcz * bpy) + ny * (bcz * bpx - bcx * bpz) + nz * (bcx * bpy - bcy * bpx);
    const Vec8f sc = nx * (cay * cpz - caz * cpy) + ny * (caz * cpx - cax * cpz) + nz * (cax * cpy - cay * cpx);
    const Vec8f plane = nx * apx + ny * apy + nz * apz;
    const Vec8f eAB = segmentDistance2(px, py, pz, ax, ay, az, bx, by, bz, load8(&b.lane[12][m]));
    const Vec8f eBC = segmentDistance2(px, py, pz, bx, by, bz, cx, cy, cz, load8(&b.lane[13][m]));
    const Vec8f eCA = segmentDistance2(px, py, pz, cx, cy, cz, ax, ay, az, load8(&b.lane[14][m]));
    const Vec8f edges = min8(min8(eAB, eBC), eCA);
    const Vec8f smallest = min8(min8(sa, sb), sc);
    store8(&b.lane[15][m], smallest >= tol ? min8(plane * plane, edges) : edges);
  }
}

// Exact closest triangle to p among `list` (which must hold p's closest triangle); ioBest2/ioPosition carry
// a warm start (a triangle and its exact squared distance). Three stages, each cheaper than the next:
// box lower bounds for every candidate (vectorized), a float point-triangle distance for the survivors
// (vectorized), then exact double distances by increasing float estimate until the estimate (less the
// rounding allowance) exceeds the best exact distance.
SDFCCD_HOT void closestInList(const Context& ctx, const CandidateList& l, const Vec3& p, double& ioBest2,
                              int& ioPosition, ScreenBuffers& b) {
  const TriangleBvh& bvh = *ctx.bvh;
  const float* records = ctx.records->data.data();
  const float bestF = roundUp(std::sqrt(ioBest2)) + ctx.slack;
  const float threshold = bestF * bestF;
  const float px = static_cast<float>(p.x()), py = static_cast<float>(p.y()), pz = static_cast<float>(p.z());
  const std::size_t padded = l.padded;
  b.reserve(padded + 8);
  // Stage 1: box bounds; survivors compacted without branches (their pass/fail pattern is unpredictable).
  int* survivor = b.position.data();
  const int* position = l.position.data();
  std::size_t count = 0;
  for (std::size_t c = 0; c < padded; c += kChunk) {
    float d2[kChunk];
    chunkPointBox(l, c, px, py, pz, d2);
    if (!anyAtMost(d2, threshold)) continue;
    for (int m = 0; m < kChunk; ++m) {
      survivor[count] = position[c + m];
      count += d2[m] <= threshold ? 1 : 0;
    }
  }
  if (count == 0) return;
  const std::size_t lanes = (count + 7) / 8 * 8;
  for (std::size_t m = count; m < lanes; ++m) survivor[m] = survivor[0];  // padding lanes repeat the first
  float limit = threshold;
  auto test = [&](int q) {
    if (q == ioPosition) return;
    const double e2 = bvh.squaredDistance(p, q);
    if (e2 < ioBest2) {
      ioBest2 = e2;
      ioPosition = q;
      const float f = roundUp(std::sqrt(ioBest2)) + ctx.slack;
      limit = f * f;
    }
  };
  for (std::size_t start = 0; start < lanes; start += kBatch) {
    // Stage 2: gather the survivors' float triangles into SoA lanes and screen them.
    const std::size_t batch = std::min(kBatch, lanes - start);
    for (std::size_t m = 0; m < batch; ++m) {
      const float* r = records + static_cast<std::size_t>(survivor[start + m]) * TriangleRecords::kFields;
      b.lane[0][m] = r[0], b.lane[1][m] = r[1], b.lane[2][m] = r[2], b.lane[3][m] = r[3], b.lane[4][m] = r[4];
      b.lane[5][m] = r[5], b.lane[6][m] = r[6], b.lane[7][m] = r[7], b.lane[8][m] = r[8], b.lane[9][m] = r[9];
      b.lane[10][m] = r[10], b.lane[11][m] = r[11], b.lane[12][m] = r[12], b.lane[13][m] = r[13];
      b.lane[14][m] = r[14];
    }
    screenSurvivors(b, batch, px, py, pz, ctx.areaTolerance);
    // Stage 3: exact distances, the smallest estimate first (usually the answer; it tightens the limit),
    // then every other survivor whose estimate is still within the limit.
    const float* estimate = b.lane[15];
    const std::size_t real = std::min(batch, count - start);
    std::size_t first = 0;
    for (std::size_t m = 1; m < real; ++m) first = estimate[m] < estimate[first] ? m : first;
    if (estimate[first] <= limit) test(survivor[start + first]);
    for (std::size_t m = 0; m < real; ++m) {
      if (m != first && estimate[m] <= limit) test(survivor[start + m]);
    }
  }
}

// Copies the entries of `parent` whose box lies within `bound` of the node box [lo, hi] into `child`.
SDFCCD_HOT void filterList(const Context& ctx, const CandidateList& parent, const Vec3& lo, const Vec3& hi,
                           double bound, CandidateList& child) {
  const Vec8f qlx = splat8(roundDown(lo.x())), qly = splat8(roundDown(lo.y())), qlz = splat8(roundDown(lo.z()));
  const Vec8f qhx = splat8(roundUp(hi.x())), qhy = splat8(roundUp(hi.y())), qhz = splat8(roundUp(hi.z()));
  const Vec8f zero = splat8(0.0f);
  const float b = roundUp(bound) + ctx.slack;
  const float b2 = b * b;
  const std::size_t padded = parent.padded;
  child.clear();
  child.reserve(padded + kChunk);
  float* lox = child.lox.data();
  float* loy = child.loy.data();
  float* loz = child.loz.data();
  float* hix = child.hix.data();
  float* hiy = child.hiy.data();
  float* hiz = child.hiz.data();
  int* position = child.position.data();
  std::size_t count = 0;
  for (std::size_t c = 0; c < padded; c += kChunk) {
    float d2[kChunk];
    for (int m = 0; m < kChunk; m += 8) {
      const std::size_t e = c + m;
      const Vec8f gx = max8(max8(load8(&parent.lox[e]) - qhx, qlx - load8(&parent.hix[e])), zero);
      const Vec8f gy = max8(max8(load8(&parent.loy[e]) - qhy, qly - load8(&parent.hiy[e])), zero);
      const Vec8f gz = max8(max8(load8(&parent.loz[e]) - qhz, qlz - load8(&parent.hiz[e])), zero);
      store8(d2 + m, gx * gx + gy * gy + gz * gz);
    }
    if (!anyAtMost(d2, b2)) continue;
    // Branch-free compaction: every entry is written, only the passing ones advance the count.
    for (int m = 0; m < kChunk; ++m) {
      const std::size_t e = c + m;
      lox[count] = parent.lox[e], loy[count] = parent.loy[e], loz[count] = parent.loz[e];
      hix[count] = parent.hix[e], hiy[count] = parent.hiy[e], hiz[count] = parent.hiz[e];
      position[count] = parent.position[e];
      count += d2[m] <= b2 ? 1 : 0;
    }
  }
  child.size = count;
  child.pad();
}

// The nodes of a leaf box (at most 2 per side): one warm-started closestInList() per node, then the
// pseudonormal sign when the mesh is closed.
void leafNodes(const Context& ctx, const Block& box, const CandidateList& list, int warm, Scratch& s,
               float* outDistance) {
  const TriangleBvh& bvh = *ctx.bvh;
  const SdfGridLayout& layout = *ctx.layout;
  int previous = warm;
  for (int k = box.begin.z(); k < box.end.z(); ++k)
    for (int j = box.begin.y(); j < box.end.y(); ++j)
      for (int i = box.begin.x(); i < box.end.x(); ++i) {
        const Vec3 p = layout.origin + layout.spacing * Vec3(i, j, k);
        double best2 = bvh.squaredDistance(p, previous);
        int bestPosition = previous;
        closestInList(ctx, list, p, best2, bestPosition, s.screen);
        float value = static_cast<float>(std::sqrt(best2));
        if (ctx.normals != nullptr) {
          Vec3 closest;
          TriangleFeature feature;
          detail::closestPointOnTriangle(p, bvh.a(bestPosition), bvh.b(bestPosition), bvh.c(bestPosition), closest,
                                         feature);
          if ((p - closest).dot(ctx.normals->normal(bvh.triangleIndex(bestPosition), feature)) < 0.0) value = -value;
        }
        outDistance[nodeIndex(layout.nodeCounts, i, j, k)] = value;
        previous = bestPosition;
      }
}

// The corner nodes of a box of nodes in the grid's frame, its centre, and half its diagonal.
struct BlockBounds {
  Vec3 lo, hi, centre;
  double radius;
};

BlockBounds blockBounds(const SdfGridLayout& layout, const Block& box) {
  BlockBounds b;
  b.lo = layout.origin + layout.spacing * box.begin.cast<double>();
  b.hi = layout.origin + layout.spacing * (box.end - Vec3i::Ones()).cast<double>();
  b.centre = 0.5 * (b.lo + b.hi);
  b.radius = 0.5 * (b.hi - b.lo).norm();
  return b;
}

void subdivide(const Context& ctx, const Block& box, int level, const CandidateList& parent, int warm, Scratch& s,
               float* outDistance);

// Splits `box` in halves along each axis (the first half the larger) and hands every non-empty octant to
// subdivide() at `childLevel`, with `list` as its candidates and `warm` as its first guess.
void subdivideOctants(const Context& ctx, const Block& box, int childLevel, const CandidateList& list, int warm,
                      Scratch& s, float* outDistance) {
  const Vec3i half = (box.end - box.begin + Vec3i::Ones()) / 2;
  for (int oz = 0; oz < 2; ++oz)
    for (int oy = 0; oy < 2; ++oy)
      for (int ox = 0; ox < 2; ++ox) {
        const Vec3i o(ox, oy, oz);
        Block child;
        for (int a = 0; a < 3; ++a) {
          child.begin[a] = box.begin[a] + (o[a] ? half[a] : 0);
          child.end[a] = o[a] ? box.end[a] : box.begin[a] + half[a];
        }
        if ((child.end.array() <= child.begin.array()).any()) continue;
        subdivide(ctx, child, childLevel, list, warm, s, outDistance);
      }
}

// A box of nodes whose candidates are `parent` (a superset of every node's closest triangle): tightens the
// list to this box (bound: exact centre distance + half-diagonal) and recurses into octants down to 2^3.
void subdivide(const Context& ctx, const Block& box, int level, const CandidateList& parent, int warm, Scratch& s,
               float* outDistance) {
  const BlockBounds bounds = blockBounds(*ctx.layout, box);
  double centre2 = ctx.bvh->squaredDistance(bounds.centre, warm);
  int centrePosition = warm;
  closestInList(ctx, parent, bounds.centre, centre2, centrePosition, s.screen);
  CandidateList& list = s.level[level];
  filterList(ctx, parent, bounds.lo, bounds.hi, std::sqrt(centre2) + bounds.radius, list);
  const Vec3i size = box.end - box.begin;
  if (size.maxCoeff() <= 2 || level + 1 >= kLevels) {
    leafNodes(ctx, box, list, centrePosition, s, outDistance);
    return;
  }
  subdivideOctants(ctx, box, level + 1, list, centrePosition, s, outDistance);
}

// The distance pass of one block of up to 8^3 nodes: candidates from the BVH, then subdivide(). Writes the
// distance to outDistance, signed by the pseudonormal of the closest feature when ctx.normals is set.
void distanceBlock(const Context& ctx, const Block& block, Scratch& s, float* outDistance) {
  const TriangleBvh& bvh = *ctx.bvh;
  const BlockBounds bounds = blockBounds(*ctx.layout, block);
  double centre2 = std::numeric_limits<double>::infinity();
  int centrePosition = -1;
  bvh.closest(bounds.centre, centre2, centrePosition);
  const double bound = (std::sqrt(centre2) + bounds.radius) * tolerance::kSearchRadiusGrowth;
  s.bvhCandidates.clear();
  bvh.collectNearBox(bounds.lo, bounds.hi, bound, s.bvhCandidates);
  CandidateList& top = s.level[0];
  top.clear();
  for (const int q : s.bvhCandidates) {
    top.push(roundDown(bvh.boxLo(q).x()), roundDown(bvh.boxLo(q).y()), roundDown(bvh.boxLo(q).z()),
             roundUp(bvh.boxHi(q).x()), roundUp(bvh.boxHi(q).y()), roundUp(bvh.boxHi(q).z()), q);
  }
  top.pad();
  s.candidateTotal += top.size;
  const Vec3i size = block.end - block.begin;
  if (size.maxCoeff() <= 2) {
    leafNodes(ctx, block, top, centrePosition, s, outDistance);
    return;
  }
  subdivideOctants(ctx, block, 1, top, centrePosition, s, outDistance);
}

}  // namespace

DistancePassStats computeNodeDistances(const TriangleBvh& bvh, const SdfGridLayout& layout,
                                       const MeshPseudonormals* normals, double largestCoordinate,
                                       const std::vector<Block>& blocks, int threads, ProgressReporter& progress,
                                       float* outValues) {
  const TriangleRecords records(bvh);
  const double epsilonF = std::numeric_limits<float>::epsilon();
  const double largest = largestCoordinate;
  const Context ctx{&bvh,
                    &records,
                    &layout,
                    normals,
                    static_cast<float>(16.0 * epsilonF * largest),
                    static_cast<float>(128.0 * epsilonF * largest * largest)};
  std::vector<Scratch> scratch(static_cast<std::size_t>(threads));
  parallelFor(blocks.size(), threads, [&](std::size_t b, int thread) {
    distanceBlock(ctx, blocks[b], scratch[static_cast<std::size_t>(thread)], outValues);
    progress.advance();
  });
  DistancePassStats stats;
  std::size_t candidateTotal = 0;
  for (const Scratch& s : scratch) {
    candidateTotal += s.candidateTotal;
    stats.scratchBytes +=
        s.bvhCandidates.capacity() * sizeof(int) + s.screen.position.capacity() * sizeof(int) + sizeof(ScreenBuffers);
    for (const CandidateList& l : s.level) stats.scratchBytes += l.bytes();
  }
  stats.meanCandidates =
      static_cast<double>(candidateTotal) / static_cast<double>(std::max<std::size_t>(blocks.size(), 1));
  return stats;
}

}  // namespace sdfccd::detail
