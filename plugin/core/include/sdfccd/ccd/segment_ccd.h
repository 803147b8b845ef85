/// @file
/// @brief Continuous collision of a segment with a level set of a distance field (paper Sections 3.1, 3.2).
///
/// @details A point moving linearly during a step, p(t) = p0 + t (p1 - p0) for t in [0, 1] (both ends in the
/// field's frame), touches the level set S_sigma = {phi = sigma} when phi(p(t)) <= sigma. The query finds the
/// first such t and, on request, every maximal sub-interval of [0, 1] where phi(p(t)) <= sigma.
///
/// The settings and result types are shared by every field type (field_interface.h: GridField and the four
/// analytic fields), so the point tree and the penalty model are templates over the field and never pay a
/// virtual call.
///
/// Edge-case policy (decided here, pinned by tests):
/// - Touching counts as contact: phi == sigma is inside the contact set.
/// - A segment that starts with phi <= sigma reports StartsInside, fraction 0.
/// - Parts of the segment outside a grid field's box are free of contact; a segment entirely outside is
///   OutsideField. Analytic fields are defined everywhere.
/// - A zero-length segment is a point query at p0.
/// - Grid fields clip the segment to the box in double-double before parametrising the walk, so a segment
///   1e20 long through the field finds its contact; its fraction is then rounded to double (see `point`).
#pragma once

#include <cstdint>

#include "sdfccd/ccd/interval_list.h"
#include "sdfccd/math_types.h"

namespace sdfccd {

/// How the root inside a cell is found.
enum class CcdMethod : std::uint8_t {
  Exact,      ///< the cubic along the segment, all roots in the cell (never misses a contact)
  Bisection,  ///< eq. (2) regula falsi from the entry/exit values, at most 5 iterations; can miss (Fig. 2)
};

/// What the query computes.
enum class CcdMode : std::uint8_t {
  FirstHit,      ///< stop at the first contact (point-tree inner nodes, constraint-based haptics)
  AllIntervals,  ///< every sub-interval where phi <= sigma (penalty impulse integrals)
};

/// How cells are skipped with the min-distance octree.
enum class OctreeMode : std::uint8_t {
  Full,    ///< skip the largest octree block whose minimum exceeds sigma, searched from the root
  Leaves,  ///< skip single cells whose minimum exceeds sigma (the paper's choice at haptic rates)
  Off,     ///< visit every cell on the segment's path
};

/// Why a query ended.
enum class SegmentState : std::uint8_t {
  Separated,     ///< no contact on [0, 1]
  Hit,           ///< enters the contact set at `fraction` > 0
  StartsInside,  ///< phi(p0) <= sigma: fraction 0
  OutsideField,  ///< the whole segment lies outside the field's box (grid fields only): no contact
  Failed,        ///< non-finite input, or (grid fields) p1 - p0 overflows: no answer
};

/// Settings of one query.
struct SegmentCcdSettings {
  double sigma = 0.0;                    ///< level set value (model units); a node radius in the point tree
  CcdMethod method = CcdMethod::Exact;   ///< root finding per cell
  CcdMode mode = CcdMode::FirstHit;      ///< first contact only, or every interval
  OctreeMode octree = OctreeMode::Full;  ///< cell skipping (grid fields only)
  /// FirstHit mode only (AllIntervals ignores it): look for a contact on [0, maxFraction] of the segment only;
  /// a contact after it is reported as Separated. A search that can stop early (the earliest contact of a
  /// body, branch and bound) walks fewer cells. The fraction found on the shorter walk can differ in the last
  /// bits from the full walk's, so callers that need bit-identical answers re-run the full query on a hit.
  double maxFraction = 1.0;
};

/// The answer to one query.
struct SegmentCcdResult {
  SegmentState state = SegmentState::Separated;
  double fraction = 1.0;       ///< first t in [0,1] with phi <= sigma; 1 when there is none
  IntervalList intervals;      ///< AllIntervals mode: sorted, disjoint, merged [a, b] where phi <= sigma
  Vec3 normal = Vec3::Zero();  ///< at the first contact: normalized field gradient (zero if undefined)
  /// The first contact point in the field's frame (zero when there is none). For a grid field and a segment far
  /// longer than the field (over 2^26 cells), `fraction` is rounded to double and p0 + fraction (p1 - p0) can
  /// lie far from the contact; `point` is exact to the field's resolution.
  Vec3 point = Vec3::Zero();
  double depth = 0.0;  ///< at the first contact: phi - sigma (0 at a crossing, < 0 when starting inside)

  bool hit() const { return state == SegmentState::Hit || state == SegmentState::StartsInside; }
};

}  // namespace sdfccd
