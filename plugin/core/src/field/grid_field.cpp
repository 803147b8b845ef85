/// @file
/// @brief GridField: the segment query against a grid SDF with its min-distance octree (Sections 3.1, 3.2).
#include "sdfccd/field/grid_field.h"

#include <cmath>
#include <mutex>

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

}  // namespace

void GridField::intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                                 SegmentCcdResult& outResult) const {
  outResult.intervals.clear();
  outResult.fraction = 1.0;
  outResult.normal.setZero();
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
  Vec3 grad;
  const double phi = grid.interpolate(pointInSdf, grad);
  // Depth: 0 at a crossing (the computed phi - sigma there is rounding noise), phi - sigma < 0 when the
  // contact starts inside (at p0, or where the segment enters the box).
  outResult.depth = found.first > tBegin ? 0.0 : std::min(0.0, phi - settings.sigma);
  const double norm = grad.norm();
  if (norm > 0.0 && std::isfinite(norm)) outResult.normal = grad / norm;
}

}  // namespace sdfccd
