/// @file
/// @brief RigidCcdCoherence: the history of one shell's every-contact queries against one field (one pair and
/// role of a simulation), which lets the next query start from the last one's front instead of the tree's root.
///
/// @details The front is a cut of the point tree (every leaf lies below exactly one front node), in depth-first
/// order: the nodes where the last query stopped (culled inner nodes and queried leaves). Each front node may
/// carry a certificate taken at some earlier pose P_k of the shell in the field's frame:
///   - Phi: phi(centre at P_k) = clearance, with the centre inside the field's box (or an unbounded field);
///   - Box: the centre at P_k lies `clearance` outside the field's box (no contact is possible outside it).
/// A point x below the node moves at most d = ||R - R_k||_F (|c| + rho) + |t - t_k| away from its position at
/// P_k during the step (the segment's ends bound it; the Frobenius norm bounds the rotation's). So the node
/// cannot touch when clearance - L (rho + d) > sigma (Phi; L the field's gradient bound) or clearance > rho + d
/// (Box), with slack against rounding. Such a node is skipped with no field lookup; any other front node is
/// first tried against a fresh certificate at the step's end pose (one lookup: enough when the step is shorter
/// than the clearance), then tested as the fresh traversal tests it and expanded (descent), and the new front's
/// complete sibling groups whose parent is certified with room to spare are replaced by the parent (ascent; the
/// parent's centre is its first child's, so the first child's certificate is the parent's). Leaves run the same point
/// query as the fresh traversal, so the contacts are the fresh query's bit for bit (tested), in the same order (by
/// point).
///
/// Ownership: the caller keeps one per (shell, field) pair and role and passes it to every query of that pair;
/// a query with another tree, field, sigma or gradient bound starts afresh. Tree and field are told apart by their
/// instance ids (instance_id.h), never by address, so a new object at a freed one's address starts afresh too;
/// the analytic plane and box (per-step locals in Bullet) by their values, which say all there is to them; other
/// fields (the sphere, capsule and triangle fields) run the fresh query and reset the history. Not thread safe:
/// one query at a time.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "sdfccd/math_types.h"

namespace sdfccd {

class AxisLipschitzBounds;

class RigidCcdCoherence {
 public:
  /// Forgets the history: the next query starts at the root.
  void reset() {
    front.clear();
    frontBound = {};
    frontCertified = false;
    poses.clear();
    posesAfterCompaction = 0;
    lastEndValid = false;
    tables.reset();
    axisBounds.reset();
    treeId = 0;
    fieldId = 0;
    fieldValue = {};
  }
  /// Front nodes after the last query (0 before the first).
  std::size_t frontSize() const { return front.size(); }

  // The state below belongs to the query (src/ccd/rigid_ccd_coherent.h); callers only keep the object.
  enum class Kind : std::uint8_t { None, Phi, Box };
  struct Entry {
    int node = 0;
    int pose = -1;  // index into `poses` (certified entries)
    double clearance = 0.0;
    double room = 0.0;  // how far below the centre (radius + motion) the certificate allows
    Kind kind = Kind::None;
    int block = -1;  // axis certificate: the AxisLipschitzBounds block of the centre (-1: none)
  };
  /// The front's certificates folded into one test at the newest kept pose `poses.back()` (the whole-front
  /// test, coherentFrontClear): the largest reach from the shell origin and the smallest room left over a node's
  /// radius and over the motion from its certificate's pose to the newest (room / kBoundGrowth - radius - that),
  /// over the front's entries (and possibly more: a superset is only more conservative).
  struct FrontBound {
    double maxReach = 0.0;
    double minSlack = 0.0;
  };
  std::vector<Entry> front;
  FrontBound frontBound;        // valid when frontCertified
  bool frontCertified = false;  // every front entry carries a certificate (none is a contact or ignored)
  /// Per-tree tables, the same for every history of one tree: shared (rigidCcdTreeTables in the query), so
  /// that hundreds of pairs of one shape keep one copy warm in the cache instead of one each.
  struct TreeTables {
    std::vector<int> parent;              // per tree node (-1: root)
    std::vector<double> reachFromOrigin;  // per node: |centre| + radius, shell frame
  };
  std::vector<Rigid> poses;  // sdfFromShell at each certificate's pose
  /// Opt-in: Phi certificates also record their centre's block of the field's per-axis gradient bounds
  /// (axis_lipschitz_bounds.h; GridField only), and a node whose certificate fails by its motion's length is
  /// tried again with the motion split per axis (src/ccd/rigid_ccd_axis_certificate.h): motion along a wall
  /// then costs no clearance. Costs one pass over the field's cells on the first query (shared per field).
  bool axisCertificates = false;
  std::shared_ptr<const AxisLipschitzBounds> axisBounds;
  std::shared_ptr<const TreeTables> tables;
  std::uint64_t treeId = 0;   // the key: a query with other inputs starts afresh. Instance ids (instance_id.h),
  std::uint64_t fieldId = 0;  // not addresses: a new tree or field at a freed one's address must not match
  std::array<double, 4> fieldValue{};  // a field keyed by value (the analytic plane and box): its numbers
  int nodeCount = 0;
  double sigma = 0.0;
  double lipschitz = 0.0;
  std::uint64_t queries = 0;             // coherent queries run (paces the ascent of kept nodes)
  std::size_t posesAfterCompaction = 0;  // poses kept by the last compaction (paces the next)
  /// The last query's end pose (the newest kept pose: the whole-front test reads it here) and each kept pose's
  /// distance to it (||R_end - R_k||_F, |t_end - t_k|, and per
  /// axis the rows' and the translation's): a query that starts where the last one ended (every step of a
  /// simulation) takes its start pose's distances from here instead of recomputing them (the same numbers).
  Rigid lastEnd = Rigid::Identity();
  bool lastEndValid = false;
  std::vector<double> lastRotationToEnd;
  std::vector<double> lastTranslationToEnd;
  std::vector<Vec3> lastAxisToEnd;  // 2 per pose, as scratchAxisMotion (empty without axis certificates)
  // The axis certificates' reused buffers (the query's others are its thread's: rigid_ccd_query.h).
  std::vector<Vec3> scratchAxisMotion;
  std::vector<Vec3> scratchAxisToEnd;
};

}  // namespace sdfccd
