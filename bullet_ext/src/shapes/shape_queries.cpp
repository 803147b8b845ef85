/// @file
/// @brief SdfccdShape's ray and convex-sweep queries (see sdfccd_shape.h, "Queries").
///
/// @details Bullet 3.24 hands a concave shape of a custom type only processAllTriangles(callback, box) with the
/// query's whole box, and would test every triangle in it. Here the callback is recognised
/// (btTriangleRaycastCallback: m_from, m_to; btTriangleConvexcastCallback: the swept shape and its two poses)
/// and the distance field says where along the query the surface can be:
/// - The *band*: every point of a triangle has phi <= kBandCells cells (trilinear interpolation of a
///   1-Lipschitz distance errs by less than a cell diagonal only at features; a cell elsewhere). A ray crosses a
///   triangle only where phi <= band; a convex of bounding radius r touches one only where the centre's phi
///   <= band + r.
/// - The exact segment query of the field (GridField::intersectSegment, FirstHit, sigma = band [+ r]) finds the
///   first fraction where the query enters that level set, skipping empty space with the octree.
/// - From there the query advances in chunks: the triangles near each chunk (TriangleBuckets) go to Bullet's
///   own per-triangle callback, which computes the exact hit, the triangle's normal, Bullet's flags
///   (back-face filtering, unflipped normals) and reports to the user's result callback. After each chunk the
///   walk stops once the callback's m_hitFraction (lowered by a closest-hit callback) is behind it, or asks the
///   field again for the next entry into the band.
/// So the answer is the triangle mesh's answer (same triangles, same arithmetic as btBvhTriangleMeshShape's
/// rayTest), and only the triangles near the surface crossings are tested. Every triangle is handed over at
/// most once per query (all-hits callbacks see each crossing once).
#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <BulletCollision/CollisionShapes/btTriangleShape.h>
#include <BulletCollision/NarrowPhaseCollision/btContinuousConvexCollision.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <memory>
#include <mutex>
#include <vector>

#include "common/bullet_conversions.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "shapes/triangle_buckets.h"

namespace sdfccd::bullet {

namespace detail {

TriangleBuckets::TriangleBuckets(const TriangleMesh& mesh, double bucketSize) : m_size(bucketSize) {
  Box3 box;
  for (const Vec3& v : mesh.vertices) box.extend(v);
  if (box.isEmpty()) box = Box3(Vec3::Zero(), Vec3::Zero());
  m_origin = box.min();
  for (int axis = 0; axis < 3; ++axis) {
    m_counts[axis] = std::max(1, static_cast<int>(std::ceil(box.sizes()[axis] / m_size)) + 1);
  }
  const std::size_t bucketCount =
      static_cast<std::size_t>(m_counts.x()) * static_cast<std::size_t>(m_counts.y()) * m_counts.z();
  // Two passes: count per bucket, then fill (compressed rows).
  std::vector<int> counts(bucketCount + 1, 0);
  auto forEachBucket = [&](const std::array<int, 3>& tri, auto&& visit) {
    Box3 tbox;
    for (int k = 0; k < 3; ++k) tbox.extend(mesh.vertices[static_cast<std::size_t>(tri[static_cast<std::size_t>(k)])]);
    Vec3i a, b;
    if (!bucketRange(tbox.min(), tbox.max(), a, b)) return;
    for (int k = a.z(); k <= b.z(); ++k)
      for (int j = a.y(); j <= b.y(); ++j)
        for (int i = a.x(); i <= b.x(); ++i) visit(index(i, j, k));
  };
  for (const auto& tri : mesh.triangles) forEachBucket(tri, [&](std::size_t bucket) { ++counts[bucket + 1]; });
  for (std::size_t b = 0; b < bucketCount; ++b) counts[b + 1] += counts[b];
  m_offsets = counts;
  m_triangles.assign(static_cast<std::size_t>(m_offsets.back()), 0);
  for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) {
    forEachBucket(mesh.triangles[static_cast<std::size_t>(t)],
                  [&](std::size_t bucket) { m_triangles[static_cast<std::size_t>(counts[bucket]++)] = t; });
  }
}

}  // namespace detail

namespace {

constexpr double kBandCells = 1.5;    // the band around the field's zero set that holds every triangle (cells)
constexpr double kChunkCells = 2.0;   // length of one chunk of the walk (cells; at least the padding)
constexpr double kBucketCells = 2.0;  // bucket edge of the triangle lookup (cells)

/// Per-thread scratch of the queries: the current chunk's candidates, and a stamp per triangle index saying
/// which query handed it over last (so no triangle is handed over twice in one query, without sorting).
/// A triangle the chunk's path misses is not stamped: a later chunk may need it.
struct QueryScratch {
  std::vector<int> chunk;
  std::vector<std::uint32_t> stamps;
  std::uint32_t query = 0;

  /// Starts a query over `triangles` triangles.
  void begin(std::size_t triangles) {
    if (stamps.size() < triangles) stamps.resize(triangles, 0);
    if (++query == 0) {  // wrapped: old stamps could match again
      std::fill(stamps.begin(), stamps.end(), 0);
      query = 1;
    }
  }
  /// True the first time `index` is seen in this query (and marks it).
  bool firstTime(int index) {
    std::uint32_t& stamp = stamps[static_cast<std::size_t>(index)];
    if (stamp == query) return false;
    stamp = query;
    return true;
  }
  bool seen(int index) const { return stamps[static_cast<std::size_t>(index)] == query; }
};

/// The scratch of one query on this thread, leased for the query's duration. A result callback may cast again
/// from inside a query (Bullet's reportHit calls the user's addSingleResult, which may call rayTest): the nested
/// query leases the next scratch of this thread's stack, so the outer query's candidate list and stamps stay
/// intact. One scratch per nesting depth, kept for the thread's lifetime (no allocation per query).
class ScratchLease {
 public:
  ScratchLease() {
    Stack& stack = threadStack();
    if (stack.depth == stack.scratches.size()) stack.scratches.push_back(std::make_unique<QueryScratch>());
    m_scratch = stack.scratches[stack.depth++].get();
  }
  ~ScratchLease() { --threadStack().depth; }
  ScratchLease(const ScratchLease&) = delete;
  ScratchLease& operator=(const ScratchLease&) = delete;
  QueryScratch& operator*() const { return *m_scratch; }

 private:
  struct Stack {
    std::vector<std::unique_ptr<QueryScratch>> scratches;  // unique_ptr: growing the stack moves no scratch
    std::size_t depth = 0;
  };
  static Stack& threadStack() {
    thread_local Stack stack;
    return stack;
  }
  QueryScratch* m_scratch = nullptr;
};

/// The fractions [t0, t1] of the segment a + t (b - a) inside `box` (slab clipping); false when it misses.
bool clipToBox(const Vec3& a, const Vec3& b, const Box3& box, double& t0, double& t1) {
  t0 = 0.0;
  t1 = 1.0;
  const Vec3 d = b - a;
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] == 0.0) {
      if (a[axis] < box.min()[axis] || a[axis] > box.max()[axis]) return false;
      continue;
    }
    double ta = (box.min()[axis] - a[axis]) / d[axis];
    double tb = (box.max()[axis] - a[axis]) / d[axis];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (!(t0 <= t1)) return false;
  }
  return true;
}

/// Bullet's btTriangleConvexcastCallback never lowers its m_hitFraction, so a walk could not stop at the first
/// hit. This filter runs the very cast Bullet's processTriangle runs (btContinuousConvexCollision, the same
/// margin and allowed penetration, the same normal test), keeps the closest fraction, and hands Bullet's
/// callback only the triangles that bring it closer: Bullet then recomputes and reports them. A closest-hit
/// result callback sees the same closest hit as with every triangle (later, farther hits are not reported).
class ClosestSweepFilter : public btTriangleCallback {
 public:
  explicit ClosestSweepFilter(btTriangleConvexcastCallback* sweep) : closest(sweep->m_hitFraction), m_sweep(sweep) {}
  void processTriangle(btVector3* triangle, int partId, int triangleIndex) override {
    btTriangleShape triangleShape(triangle[0], triangle[1], triangle[2]);
    triangleShape.setMargin(m_sweep->m_triangleCollisionMargin);
    btVoronoiSimplexSolver simplexSolver;
    btGjkEpaPenetrationDepthSolver penetrationSolver;
    btContinuousConvexCollision caster(m_sweep->m_convexShape, &triangleShape, &simplexSolver, &penetrationSolver);
    btConvexCast::CastResult result;
    result.m_fraction = btScalar(1.);
    result.m_allowedPenetration = m_sweep->m_allowedPenetration;
    if (!caster.calcTimeOfImpact(m_sweep->m_convexShapeFrom, m_sweep->m_convexShapeTo, m_sweep->m_triangleToWorld,
                                 m_sweep->m_triangleToWorld, result)) {
      return;
    }
    if (!(result.m_normal.length2() > btScalar(0.0001)) || !(result.m_fraction < closest)) return;
    closest = result.m_fraction;
    m_sweep->processTriangle(triangle, partId, triangleIndex);
  }
  btScalar closest;  ///< the closest fraction so far (the walk stops behind it)

 private:
  btTriangleConvexcastCallback* m_sweep;
};

}  // namespace

/// Built on the first query (thread safe): the triangle lookup and how far the field reaches past the mesh.
struct SdfccdShape::QueryAccel {
  std::once_flag once;
  std::unique_ptr<detail::TriangleBuckets> buckets;
  Box3 meshBox;
  /// The smallest distance from a mesh vertex to the field box's boundary (field frame): a band wider than this
  /// would need phi outside the box, where the grid reports no contact.
  double fieldReach = 0.0;
};

std::shared_ptr<SdfccdShape::QueryAccel> SdfccdShape::makeQueryAccel() {
  return std::make_shared<QueryAccel>();
}

const SdfccdShape::QueryAccel& SdfccdShape::queryAccel() const {
  QueryAccel& accel = *m_queryAccel;
  std::call_once(accel.once, [&] {
    const TriangleMesh& mesh = m_model->meshInBody();
    accel.buckets = std::make_unique<detail::TriangleBuckets>(mesh, kBucketCells * m_model->cellSize());
    const Rigid fieldFromBody = m_model->bodyFromField().inverse();
    const Box3 fieldBox = m_model->field().grid().box();
    double reach = BT_LARGE_FLOAT;
    for (const Vec3& v : mesh.vertices) {
      accel.meshBox.extend(v);
      const Vec3 p = fieldFromBody * v;
      reach = std::min(reach, std::min((p - fieldBox.min()).minCoeff(), (fieldBox.max() - p).minCoeff()));
    }
    accel.fieldReach = reach;
  });
  return accel;
}

void SdfccdShape::feedTrianglesNear(btTriangleCallback* callback, const btScalar& hitFraction, const Vec3& from,
                                    const Vec3& to, double radius) const {
  const QueryAccel& accel = queryAccel();
  const double cell = m_model->cellSize();
  const double pad = kBandCells * cell + radius;  // how far from the path a triangle can matter
  const double length = (to - from).norm();
  // Only the part of the path within `pad` of the mesh's box can meet a triangle.
  double tBegin = 0.0, tEnd = 1.0;
  Box3 grown = accel.meshBox;
  grown.min().array() -= pad;
  grown.max().array() += pad;
  if (!clipToBox(from, to, grown, tBegin, tEnd)) return;
  const double chunk = length > 0.0 ? std::max(kChunkCells * cell, pad) / length : 1.0;
  // The field can say where the band starts only if the band stays inside its box.
  const bool useField = pad < accel.fieldReach;
  const Rigid fieldFromBody = m_model->bodyFromField().inverse();
  SegmentCcdSettings settings;
  settings.sigma = pad;
  settings.mode = CcdMode::FirstHit;
  SegmentCcdResult result;
  const ScratchLease lease;
  QueryScratch& scratch = *lease;
  const TriangleMesh& mesh = m_model->meshInBody();
  scratch.begin(mesh.triangles.size());
  double t = tBegin;
  while (t <= tEnd && t < double(hitFraction)) {
    const double limit = std::min(tEnd, double(hitFraction));
    if (useField) {
      // The next entry into the band on [t, limit] (StartsInside: t is in it already).
      const Vec3 a = from + t * (to - from);
      const Vec3 b = from + limit * (to - from);
      m_model->field().intersectSegment(fieldFromBody * a, fieldFromBody * b, settings, result);
      if (result.state == SegmentState::Separated || result.state == SegmentState::OutsideField) return;
      if (result.state == SegmentState::Hit) t += result.fraction * (limit - t);
      // Failed (non-finite input): fall through and walk the triangles chunk by chunk.
    }
    const double t1 = std::min(t + chunk, limit);
    const Vec3 a = from + t * (to - from);
    const Vec3 b = from + t1 * (to - from);
    scratch.chunk.clear();
    accel.buckets->collect(a.cwiseMin(b).array() - pad, a.cwiseMax(b).array() + pad, scratch.chunk);
    btVector3 corners[3];
    for (int index : scratch.chunk) {
      if (scratch.seen(index)) continue;
      const auto& tri = mesh.triangles[static_cast<std::size_t>(index)];
      const Vec3& v0 = mesh.vertices[static_cast<std::size_t>(tri[0])];
      const Vec3& v1 = mesh.vertices[static_cast<std::size_t>(tri[1])];
      const Vec3& v2 = mesh.vertices[static_cast<std::size_t>(tri[2])];
      if (radius > 0.0) {
        // Sweeps: the chunk's path must pass through the triangle's box grown by the padding (each triangle
        // costs Bullet a continuous GJK cast). Rays: Bullet's own test is as cheap as this one.
        Box3 reach(v0.cwiseMin(v1).cwiseMin(v2).array() - pad, v0.cwiseMax(v1).cwiseMax(v2).array() + pad);
        double enter = 0.0, leave = 1.0;
        if (!clipToBox(a, b, reach, enter, leave)) continue;
      }
      scratch.firstTime(index);
      corners[0] = detail::toBt(v0);
      corners[1] = detail::toBt(v1);
      corners[2] = detail::toBt(v2);
      callback->processTriangle(corners, 0, index);
    }
    if (t1 >= tEnd) return;
    t = t1;
  }
}

bool SdfccdShape::processQuery(btTriangleCallback* callback) const {
  if (auto* ray = dynamic_cast<btTriangleRaycastCallback*>(callback)) {
    feedTrianglesNear(ray, ray->m_hitFraction, detail::toVec3(ray->m_from), detail::toVec3(ray->m_to), 0.0);
    return true;
  }
  if (auto* sweep = dynamic_cast<btTriangleConvexcastCallback*>(callback)) {
    // The swept shape's centre path in the body frame, and a sphere around its origin that holds it in any
    // orientation (Bullet's cast also rotates it from one pose to the other).
    const btTransform bodyFromWorld = sweep->m_triangleToWorld.inverse();
    btVector3 centre;
    btScalar radius = 0;
    sweep->m_convexShape->getBoundingSphere(centre, radius);
    const double reach = double(centre.length() + radius) + double(sweep->m_triangleCollisionMargin) +
                         std::max(0.0, double(sweep->m_allowedPenetration));
    ClosestSweepFilter filter(sweep);
    feedTrianglesNear(&filter, filter.closest, detail::toVec3(bodyFromWorld * sweep->m_convexShapeFrom.getOrigin()),
                      detail::toVec3(bodyFromWorld * sweep->m_convexShapeTo.getOrigin()), reach);
    return true;
  }
  return false;
}

}  // namespace sdfccd::bullet
