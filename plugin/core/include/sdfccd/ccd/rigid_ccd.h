/// @file
/// @brief Rigid CCD of a point shell (in its nested sphere tree) against a distance field (paper Section 3.3).
///
/// @details Both bodies move rigidly during a step. Each shell point's trajectory in the field's frame is
/// approximated by the segment between its start and end positions (Section 3):
///   p0 = sdfFromShellStart * x,   p1 = sdfFromShellEnd * x.
/// The tree is traversed breadth-first; a node is culled when its centre's segment does not reach the level
/// set sigma + L * node radius (first hit, exact roots, is enough for inner nodes). L is the field's gradient
/// bound (1 for analytic fields, as in the paper; computed from the values for a grid, whose trilinear
/// interpolant can be steeper, with a guard at the box faces; see field_culling_bounds.h, held by GridField). A node's
/// children are tested only from the node's first contact on: no point below it touches earlier. Leaves are queried at
/// sigma with the settings' method/mode/octree, exactly as the linear traversal (useTree = false) queries every point:
/// the linear traversal is the reference, and both return bit-identical contacts (tested).
///
/// The templates below are defined in the library (src/ccd/rigid_ccd.cpp, the traversal in
/// src/ccd/rigid_ccd_query.h) and instantiated for the five field types of field_interface.h.
///
/// Thread safety: the tree and the field are read-only; any number of queries may run at once, each with its
/// own RigidCcdResult.
#pragma once

#include <cstdint>
#include <vector>

#include "sdfccd/ccd/rigid_ccd_coherence.h"
#include "sdfccd/ccd/segment_ccd.h"
#include "sdfccd/field/field_interface.h"
#include "sdfccd/math_types.h"
#include "sdfccd/shell/point_tree.h"

namespace sdfccd {

/// Settings of one rigid CCD query.
struct RigidCcdSettings {
  double sigma = 0.0;                    ///< contact level set (field units); 0 = the surface
  CcdMethod method = CcdMethod::Exact;   ///< root finding per cell
  CcdMode mode = CcdMode::AllIntervals;  ///< what leaves compute: first hit only, or every interval
  OctreeMode octree = OctreeMode::Full;  ///< cell skipping in grid fields
  bool useTree = true;                   ///< false: point by point (the linear baseline)
  int threads = 1;                       ///< worker threads (0: all cores); results identical to serial
  /// Optional, one byte per shell point: points with a non-zero entry are skipped (the constraint method
  /// ignores the points in contact in the last step, Section 4.2). Null: no point is skipped.
  const std::vector<std::uint8_t>* ignoredPoints = nullptr;
  /// Gradient bound used to cull tree nodes (the node test is sigma + cullLipschitz * radius). 0: the field's
  /// own bound (field_culling_bounds.h: 1 for analytic fields, computed from the values for grids), which
  /// guarantees the linear query's contacts. 1 is the paper's test; it can miss contacts of a grid field
  /// whose interpolant is steeper than 1.
  double cullLipschitz = 0.0;
  /// Only the earliest contact of the body (the time of impact): outResult.firstFraction and the contact(s) at
  /// that fraction (every point whose first contact is exactly firstFraction), bit-identical to the minimum of
  /// the full query's contacts. The tree is searched depth first (branch and bound): a node whose inflated
  /// first hit comes after the best contact found so far is pruned, and once a contact is known every node
  /// and point is tested only up to it (SegmentCcdSettings::maxFraction; a point that hits there is queried
  /// again over the whole step, so its fraction is the linear query's bit for bit). The linear traversal uses
  /// the same bound point by point. This mode always runs serially (threads is ignored), so it is trivially
  /// identical for any thread count.
  bool earliestOnly = false;
  /// With earliestOnly: one contact at the earliest fraction is enough (a time-of-impact solver needs the time
  /// and one witness). The search stops as soon as no node can beat the best contact, instead of collecting
  /// every point tied at it: outResult.contacts holds exactly one contact when there is one (which one of
  /// several tied points is unspecified), and firstFraction is still bit-identical to the full query's.
  /// Bodies that start interpenetrated (many points tied at fraction 0) end after the first such point.
  bool earliestOneContact = false;
};

/// One shell point in contact during the step.
struct PointContact {
  int point = -1;                          ///< index into the shell
  SegmentState state = SegmentState::Hit;  ///< Hit or StartsInside
  double fraction = 1.0;                   ///< first contact, fraction of the step in [0, 1]
  IntervalList intervals;                  ///< AllIntervals mode: where phi <= sigma
  double depthAtEnd = 0.0;                 ///< phi(p1) - sigma (field units; < 0 penetrating at the end)
  Vec3 fieldNormalInSdf = Vec3::Zero();    ///< normalized field gradient at the first contact, field frame
  Vec3 pointNormalInShell = Vec3::Zero();  ///< the point's outward normal, shell frame
};

/// Counters of one query (for benchmarks and reports).
struct RigidCcdStats {
  std::int64_t nodesVisited = 0;    ///< tree nodes whose segment was tested
  std::int64_t segmentQueries = 0;  ///< segment queries against the field (inner nodes + leaves)
  std::int64_t certified = 0;       ///< coherent query: front nodes ruled out by their certificate alone
};

/// Every contact of the step, sorted by point index.
struct RigidCcdResult {
  std::vector<PointContact> contacts;
  double firstFraction = 1.0;  ///< the earliest contact over all points (1 when none)
  RigidCcdStats stats;

  void clear() {
    contacts.clear();
    firstFraction = 1.0;
    stats = {};
  }
};

/// The query. `Field` is one of the field types of field_interface.h. `outResult` is cleared first.
template <class Field>
void rigidCcd(const PointTree& tree, const Field& field, const Rigid& sdfFromShellStart, const Rigid& sdfFromShellEnd,
              const RigidCcdSettings& settings, RigidCcdResult& outResult);

/// The same query started from the last query's front kept in `history` (rigid_ccd_coherence.h): the contacts,
/// their order and firstFraction are the query above's bit for bit; only the stats differ. Runs serially (any
/// `threads`). Queries the coherence does not cover run as above and leave `history` untouched: earliestOnly, a
/// cullLipschitz override (whose culling may differ from the field's own bound) and the linear traversal. A field
/// without an instance id (all but GridField) runs as above and resets `history` (rigid_ccd_coherence.h).
template <class Field>
void rigidCcd(const PointTree& tree, const Field& field, const Rigid& sdfFromShellStart, const Rigid& sdfFromShellEnd,
              const RigidCcdSettings& settings, RigidCcdCoherence& history, RigidCcdResult& outResult);

/// The coherent query's fast path alone: when the certificates kept in `history` rule out every contact of
/// this step (checked once per kept pose on the front's folded bounds, rigid_ccd_coherence.h, with no field
/// lookup and no traversal), sets `outResult` to the empty answer (stats.certified = the front's size) and
/// returns true; the query above would return no contact either. Otherwise returns false and changes nothing:
/// run the query above. Always false where the query above does not use the history. The query above tries
/// this first itself; callers call it directly to skip work around a query that has nothing to do (e.g. its
/// clock: the contact query times only the queries that traverse).
template <class Field>
bool rigidCcdCertifiedClear(const PointTree& tree, const Field& field, const Rigid& sdfFromShellStart,
                            const Rigid& sdfFromShellEnd, const RigidCcdSettings& settings, RigidCcdCoherence& history,
                            RigidCcdResult& outResult);

/// The culling test of one tree node (what the traversal uses; exposed for tests): false only when no point
/// below `node` can reach the level set sigma during the step. Never false for a node with a colliding point.
template <class Field>
bool pointTreeNodeMayCollide(const PointTree& tree, const Field& field, int node, const Rigid& sdfFromShellStart,
                             const Rigid& sdfFromShellEnd, const RigidCcdSettings& settings);

}  // namespace sdfccd
