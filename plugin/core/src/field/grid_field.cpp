/// @file
/// @brief GridField: the segment query against a grid SDF with its min-distance octree (Sections 3.1, 3.2).
#include "sdfccd/field/grid_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

#include "ccd/double_double.h"
#include "ccd/segment_walk.h"
#include "sdfccd/error.h"

namespace sdfccd {

/// The culling bounds, computed once on first use.
struct GridField::LazyCullingBounds {
  std::once_flag once;
  FieldCullingBounds bounds;
};

GridField::GridField(std::shared_ptr<const SdfGrid> grid)
    : m_grid(std::move(grid)), m_cullingBounds(std::make_shared<LazyCullingBounds>()) {
  if (!m_grid) throw Error("grid field needs a grid, got none");
  if (m_grid->empty()) throw Error("grid field needs a non-empty grid");
  m_octree = MinDistanceOctree(*m_grid);
}

const FieldCullingBounds& GridField::cullingBounds() const {
  LazyCullingBounds& lazy = *m_cullingBounds;
  std::call_once(lazy.once, [&] { lazy.bounds = computeCullingBounds(*m_grid); });
  return lazy.bounds;
}

double GridField::distance(const Vec3& pointInSdf) const {
  if (m_grid->contains(pointInSdf)) return m_grid->interpolate(pointInSdf);
  // Outside the box: never in contact (policy in segment_ccd.h), and growing with the distance to the box.
  const double toBox = m_grid->box().exteriorDistance(pointInSdf);
  return toBox + std::max(0.0, m_grid->interpolate(pointInSdf));
}

Vec3 GridField::gradient(const Vec3& pointInSdf) const {
  return m_grid->gradient(pointInSdf);
}

namespace {

using WalkFunction = void (*)(const detail::WalkContext&, GridWalk&, bool, detail::WalkOutput&, IntervalList&);

template <CcdMethod kMethod, CcdMode kMode>
WalkFunction pickOctree(OctreeMode octree) {
  switch (octree) {
    case OctreeMode::Full:
      return &detail::walkSegment<kMethod, kMode, OctreeMode::Full>;
    case OctreeMode::Leaves:
      return &detail::walkSegment<kMethod, kMode, OctreeMode::Leaves>;
    case OctreeMode::Off:
      break;
  }
  return &detail::walkSegment<kMethod, kMode, OctreeMode::Off>;
}

template <CcdMethod kMethod>
WalkFunction pickMode(CcdMode mode, OctreeMode octree) {
  return mode == CcdMode::FirstHit ? pickOctree<kMethod, CcdMode::FirstHit>(octree)
                                   : pickOctree<kMethod, CcdMode::AllIntervals>(octree);
}

WalkFunction pickWalk(const SegmentCcdSettings& settings) {
  return settings.method == CcdMethod::Exact ? pickMode<CcdMethod::Exact>(settings.mode, settings.octree)
                                             : pickMode<CcdMethod::Bisection>(settings.mode, settings.octree);
}

// A segment longer than this many cells takes the long path: its part inside the box is found in
// double-double and queried as a segment of its own. Below it, t's rounding (about 1e-16 of the segment)
// stays under 1e-8 of a cell, so the ordinary walk is exact enough and pays only this comparison.
constexpr double kLongSegmentCells = 67108864.0;  // 2^26

// The segment p0 + t (p1 - p0), t in [0, 1], clipped to the box [lo, hi] in double-double: false when it
// misses the box. With p0, p1 1e20 apart, t in plain doubles cannot even tell the box's entry from its exit.
bool clipToBox(const Vec3& p0, const Vec3& p1, const Box3& box, detail::DoubleDouble& tBegin,
               detail::DoubleDouble& tEnd) {
  using detail::DoubleDouble;
  tBegin = {0.0, 0.0};
  tEnd = {1.0, 0.0};
  for (int a = 0; a < 3; ++a) {
    const DoubleDouble d = detail::twoSum(p1[a], -p0[a]);
    if (d.hi == 0.0) {  // exactly parallel to the slab
      if (p0[a] < box.min()[a] || p0[a] > box.max()[a]) return false;
      continue;
    }
    DoubleDouble t0 = detail::twoSum(box.min()[a], -p0[a]) / d;
    DoubleDouble t1 = detail::twoSum(box.max()[a], -p0[a]) / d;
    if (t1 < t0) std::swap(t0, t1);
    if (tBegin < t0) tBegin = t0;
    if (t1 < tEnd) tEnd = t1;
  }
  return !(tEnd < tBegin);
}

// p0 + t (p1 - p0) rounded to double, computed in double-double.
Vec3 pointAt(const Vec3& p0, const Vec3& p1, const detail::DoubleDouble& t) {
  Vec3 q;
  for (int a = 0; a < 3; ++a) {
    q[a] = (detail::DoubleDouble{p0[a], 0.0} + t * detail::twoSum(p1[a], -p0[a])).value();
  }
  return q;
}

// The query of a segment far longer than the field (see kLongSegmentCells): clip in double-double, run the
// ordinary query on the clipped segment [q0, q1], and map its fractions s back to t = tBegin + s (tEnd -
// tBegin), rounded to double (so the fraction of a 1e20-long segment is only good to ~1e-16 of its length;
// `point`, `normal` and `depth` come from the clipped query and keep full accuracy).
void intersectLongSegment(const GridField& field, const Vec3& p0, const Vec3& p1, const SegmentCcdSettings& settings,
                          SegmentCcdResult& outResult) {
  using detail::DoubleDouble;
  if (!(p1 - p0).allFinite()) {  // longer than the double range: no meaningful parameter
    outResult.state = SegmentState::Failed;
    return;
  }
  DoubleDouble tBegin, tEnd;
  if (!clipToBox(p0, p1, field.grid().box(), tBegin, tEnd)) {
    outResult.state = SegmentState::OutsideField;
    return;
  }
  const bool firstHit = settings.mode == CcdMode::FirstHit;
  const DoubleDouble span = tEnd - tBegin;
  SegmentCcdSettings inner = settings;
  inner.maxFraction = 1.0;
  if (firstHit && settings.maxFraction < 1.0) {
    if (DoubleDouble{settings.maxFraction, 0.0} < tBegin) {
      outResult.state = SegmentState::Separated;  // in the box only after maxFraction
      return;
    }
    // Rounded up a little: the mapped fraction is checked against maxFraction below.
    const double s = span.hi > 0.0 ? ((DoubleDouble{settings.maxFraction, 0.0} - tBegin) / span).value() : 1.0;
    inner.maxFraction = std::min(1.0, std::nextafter(s, 2.0));
  }
  const Vec3 q0 = pointAt(p0, p1, tBegin), q1 = pointAt(p0, p1, tEnd);
  SegmentCcdResult clipped;
  field.intersectSegment(q0, q1, inner, clipped);
  outResult.state = clipped.state;
  if (!clipped.hit()) return;  // Separated, OutsideField (a graze lost to rounding) or Failed

  auto toT = [&](double s) { return (tBegin + span * DoubleDouble{s, 0.0}).value(); };
  const bool startsAtP0 = tBegin.hi == 0.0 && clipped.fraction <= 0.0;
  double fraction = toT(clipped.fraction);
  // Entering the box after p0 is a hit at fraction > 0 however the rounding falls.
  if (!startsAtP0) fraction = std::max(fraction, std::numeric_limits<double>::denorm_min());
  if (firstHit && fraction > settings.maxFraction) {
    outResult.state = SegmentState::Separated;
    return;
  }
  outResult.state = startsAtP0 ? SegmentState::StartsInside : SegmentState::Hit;
  outResult.fraction = startsAtP0 ? 0.0 : fraction;
  outResult.normal = clipped.normal;
  outResult.depth = clipped.depth;
  outResult.point = clipped.point;
  for (std::size_t n = 0; n < clipped.intervals.size(); ++n) {
    const Interval& interval = clipped.intervals[n];
    detail::appendMerged(outResult.intervals, interval.begin <= 0.0 && startsAtP0 ? 0.0 : toT(interval.begin),
                         toT(interval.end));
  }
}

}  // namespace

void GridField::intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                                 SegmentCcdResult& outResult) const {
  outResult.intervals.clear();
  outResult.fraction = 1.0;
  outResult.normal.setZero();
  outResult.point.setZero();
  outResult.depth = 0.0;
  if (!p0InSdf.allFinite() || !p1InSdf.allFinite() || !std::isfinite(settings.sigma)) {
    outResult.state = SegmentState::Failed;
    return;
  }
  const SdfGrid& grid = *m_grid;
  const Vec3i cells = grid.cellCounts();
  // Grid-index coordinates relative to the origin: exact enough however far the field is from zero.
  const double invSpacing = 1.0 / grid.spacing();
  const Vec3 u0 = (p0InSdf - grid.origin()) * invSpacing;
  Vec3 d = (p1InSdf - grid.origin()) * invSpacing - u0;
  if (!(d.cwiseAbs().maxCoeff() <= kLongSegmentCells)) {  // also NaN from overflowing coordinates
    intersectLongSegment(*this, p0InSdf, p1InSdf, settings, outResult);
    return;
  }

  // Clip to the box [0, cells] (slabs). Axes whose 1/d overflows do not move (as in GridWalk).
  double tBegin = 0.0, tEnd = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double inv = d[a] != 0.0 ? 1.0 / d[a] : 0.0;
    if (!std::isfinite(inv) || inv == 0.0) {
      d[a] = 0.0;
      if (u0[a] < 0.0 || u0[a] > cells[a]) tBegin = 2.0;  // parallel to the slab and outside it
      continue;
    }
    double t0 = (0.0 - u0[a]) * inv, t1 = (static_cast<double>(cells[a]) - u0[a]) * inv;
    if (t0 > t1) std::swap(t0, t1);
    tBegin = std::max(tBegin, t0);
    tEnd = std::min(tEnd, t1);
  }
  if (!(tBegin <= tEnd)) {
    outResult.state = SegmentState::OutsideField;
    return;
  }
  if (settings.mode == CcdMode::FirstHit && settings.maxFraction < tEnd) {
    tEnd = settings.maxFraction;
    if (!(tBegin <= tEnd)) {
      outResult.state = SegmentState::Separated;  // in the box only after maxFraction
      return;
    }
  }

  detail::WalkContext context;
  context.values = grid.values().data();
  context.strideY = static_cast<std::size_t>(grid.nodeCounts().x());
  context.strideZ = context.strideY * static_cast<std::size_t>(grid.nodeCounts().y());
  context.octree = &m_octree;
  context.sigma = settings.sigma;
  GridWalk walk(u0, d, cells, tBegin, tEnd);
  detail::WalkOutput found;
  pickWalk(settings)(context, walk, tBegin == tEnd, found, outResult.intervals);

  if (!found.found) {
    outResult.state = SegmentState::Separated;
    return;
  }
  // Touching counts as contact; fraction 0 can only come from p0 itself (the walk starts at p0 when p0 is
  // in the box, and later otherwise).
  outResult.fraction = found.first;
  outResult.state = found.first <= 0.0 ? SegmentState::StartsInside : SegmentState::Hit;
  const Vec3 pointInSdf = found.first <= 0.0 ? p0InSdf : Vec3(p0InSdf + found.first * (p1InSdf - p0InSdf));
  outResult.point = pointInSdf;
  Vec3 grad;
  const double phi = grid.interpolate(pointInSdf, grad);
  // Depth: 0 at a crossing (the computed phi - sigma there is rounding noise), phi - sigma < 0 when the
  // contact starts inside (at p0, or where the segment enters the box).
  outResult.depth = found.first > tBegin ? 0.0 : std::min(0.0, phi - settings.sigma);
  const double norm = grad.norm();
  if (norm > 0.0 && std::isfinite(norm)) outResult.normal = grad / norm;
}

}  // namespace sdfccd
