/// @file
/// @brief GridField: a grid SDF plus its min-distance octree, the field the CCD queries run against.
///
/// @details The octree is built bottom-up from the grid when the field is made (paper Section 3.2); it is
/// never stored on disk. The culling bounds of the point tree (field_culling_bounds.h) are computed on first
/// use and held by the field (shared by its copies). GridField is immutable after construction (the lazy
/// bounds are computed once, under std::call_once) and safe to query from many threads. It provides the
/// field interface of field_interface.h, as the four analytic fields do.
///
/// intersectSegment works in grid-index coordinates relative to the origin: it clips the segment to the box,
/// walks the cells with a 3D DDA (grid_walk.h) and, per cell, finds every sub-interval where the cubic of
/// the trilinear interpolant along the segment is <= sigma (cell_cubic.h, cubic_roots.h) or runs eq. (2)
/// (bisection). Octree modes: Off solves every cell on the path; Leaves skips a cell whose eight corners all
/// exceed sigma; Full first looks for the largest min-pyramid block around the cell whose minimum exceeds
/// sigma and jumps to the segment's exit from it, then tests the cell like Leaves. All three return
/// bit-identical results. The hot loop is a template over method, mode and octree mode (src/segment_walk.h)
/// and allocates nothing unless a segment has more than IntervalList::kInline intervals.
#pragma once

#include <memory>

#include "sdfccd/ccd/segment_ccd.h"
#include "sdfccd/field/field_culling_bounds.h"
#include "sdfccd/field/field_interface.h"
#include "sdfccd/field/min_distance_octree.h"
#include "sdfccd/field/sdf_grid.h"
#include "sdfccd/instance_id.h"

namespace sdfccd {

class GridField {
 public:
  /// Builds the octree over `grid`. Throws sdfccd::Error if grid is null or empty.
  explicit GridField(std::shared_ptr<const SdfGrid> grid);

  const SdfGrid& grid() const { return *m_grid; }
  const std::shared_ptr<const SdfGrid>& gridPtr() const { return m_grid; }
  const MinDistanceOctree& octree() const { return m_octree; }
  double spacing() const { return m_grid->spacing(); }  ///< cell edge length (model units)
  bool contains(const Vec3& pointInSdf) const { return m_grid->contains(pointInSdf); }

  /// phi at a point: trilinear inside the box; outside it, the distance to the box plus the clamped value's
  /// positive part (always > 0, so a point outside the box is never in contact). Model units.
  double distance(const Vec3& pointInSdf) const;
  /// Gradient of the trilinear interpolant (clamped to the box); not normalized.
  Vec3 gradient(const Vec3& pointInSdf) const;

  /// The segment query (see segment_ccd.h). `outResult` is overwritten; reusing one across calls avoids
  /// allocation when there are more than IntervalList::kInline intervals.
  void intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
                        SegmentCcdResult& outResult) const;

  /// The point tree's culling bounds of this grid (computed on the first call, O(cells); thread safe).
  const FieldCullingBounds& cullingBounds() const;

  /// Bytes held by the grid values plus the octree.
  std::size_t memoryBytes() const { return m_grid->memoryBytes() + m_octree.memoryBytes(); }
  /// Names this field's contents (never reused, unlike its address): keys caches such as RigidCcdCoherence.
  std::uint64_t instanceId() const { return m_id.value(); }

 private:
  struct LazyCullingBounds;

  InstanceId m_id;
  std::shared_ptr<const SdfGrid> m_grid;
  MinDistanceOctree m_octree;
  std::shared_ptr<LazyCullingBounds> m_cullingBounds;  // shared by copies: they share the grid
};

}  // namespace sdfccd
