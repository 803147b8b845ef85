/// @file
/// @brief detail::RigidCcdQuery: the traversal behind rigidCcd() (paper Section 3.3; see rigid_ccd.h). Private
/// to the core: rigid_ccd.cpp instantiates it for the field types (field_interface.h).
///
/// @details One traversal routine serves the serial and the threaded query. Per call, the two poses are
/// split into rotation and translation once; the frontiers and the segment scratch are thread_local and
/// keep their capacity, so the steady state allocates nothing per node (a contact with more than
/// IntervalList::kInline intervals allocates its own overflow). Every point's segment is computed by the same
/// function in the tree and the linear query, so both run bit-identical leaf queries.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "inline_vector_ops.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/ccd/rigid_ccd_coherence.h"
#include "sdfccd/error.h"
#include "sdfccd/field/field_interface.h"
#include "sdfccd/parallel_for.h"
#include "sdfccd/tolerances.h"

namespace sdfccd {
namespace detail {

/// A node to visit, and the fraction of the step before which no point below it can touch (its parent's
/// first contact with the parent's inflated level set).
struct NodeTask {
  int node;
  double tStart;
};

/// Per-thread buffers of the traversal, reused across queries.
struct RigidCcdScratch {
  std::vector<NodeTask> current;
  std::vector<NodeTask> next;
  std::vector<NodeTask> frontier;  // the threaded query's work items (the calling thread also runs tasks)
  SegmentCcdResult segment;
  // The coherent query's (rigid_ccd_coherent.h) buffers of one query: per thread, not per history, so that a
  // pile's ~2,000 histories a step write their new fronts into memory this thread has just used (a buffer per
  // history would be cold at every query, a step after its last use), and each history keeps only what lasts.
  std::vector<RigidCcdCoherence::Entry> front;  // the new front, copied into the history at the end
  std::vector<int> stack;                       // the fresh traversal below a node
  std::vector<double> rotation;                 // per kept pose (CoherentQuery's members of the same names)
  std::vector<double> translation;
  std::vector<double> rotationToEnd;
  std::vector<double> translationToEnd;
  std::vector<int> remap;  // compactPoses: old pose index to new
};

inline RigidCcdScratch& rigidCcdScratch() {
  thread_local RigidCcdScratch scratch;
  return scratch;
}

/// Does segment [a, b] meet the box? (slab test) `outEnter`: the fraction where it enters the box (0 if a is inside).
inline bool segmentMeetsBox(const Vec3& a, const Vec3& b, const Box3& box, double& outEnter) {
  double t0 = 0.0;
  double t1 = 1.0;
  const Vec3 d = b - a;
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] == 0.0) {
      if (a[axis] < box.min()[axis] || a[axis] > box.max()[axis]) return false;
      continue;
    }
    const double inv = 1.0 / d[axis];
    double enter = (box.min()[axis] - a[axis]) * inv;
    double leave = (box.max()[axis] - a[axis]) * inv;
    if (enter > leave) std::swap(enter, leave);
    t0 = std::max(t0, enter);
    t1 = std::min(t1, leave);
    if (t0 > t1) return false;
  }
  outEnter = t0;
  return true;
}

template <class Field>
class RigidCcdQuery {
 public:
  RigidCcdQuery(const PointTree& tree, const Field& field, const Rigid& sdfFromShellStart, const Rigid& sdfFromShellEnd,
                const RigidCcdSettings& settings)
      : m_tree(tree),
        m_field(field),
        m_settings(settings),
        m_r0(sdfFromShellStart.linear()),
        m_r1(sdfFromShellEnd.linear()),
        m_t0(sdfFromShellStart.translation()),
        m_t1(sdfFromShellEnd.translation()),
        m_bounds(fieldCullingBounds(field)) {
    if (!finiteValues(m_r0.data(), 9) || !finiteValues(m_r1.data(), 9) || !finiteValues(m_t0.data(), 3) ||
        !finiteValues(m_t1.data(), 3)) {
      throw Error("rigidCcd: non-finite transform");
    }
    if (!std::isfinite(settings.sigma)) throw Error("rigidCcd: non-finite sigma");
    if (settings.cullLipschitz < 0.0 || !std::isfinite(settings.cullLipschitz)) {
      throw Error("rigidCcd: cullLipschitz must be finite and >= 0");
    }
    if (settings.ignoredPoints && settings.ignoredPoints->size() != static_cast<std::size_t>(tree.pointCount())) {
      throw Error("rigidCcd: ignoredPoints must have one entry per shell point");
    }
    if (settings.cullLipschitz > 0.0) m_bounds.lipschitz = settings.cullLipschitz;
    m_leaf.sigma = settings.sigma;
    m_leaf.method = settings.method;
    m_leaf.mode = settings.mode;
    m_leaf.octree = settings.octree;
    // Inner nodes only need to know whether there is a contact; the exact method never misses one.
    m_node = m_leaf;
    m_node.mode = CcdMode::FirstHit;
    m_node.method = CcdMethod::Exact;
  }

  // Eigen's `m_r0 * x + m_t0`, written out and forced inline (inline_vector_ops.h): left to the compiler, both
  // Eigen's expression and these functions stayed calls, one per point.
  SDFCCD_FORCE_INLINE Vec3 startOf(const Vec3& pointInShell) const {
    return detail::scalar_ops::transformPoint(m_r0, pointInShell, m_t0);
  }
  SDFCCD_FORCE_INLINE Vec3 endOf(const Vec3& pointInShell) const {
    return detail::scalar_ops::transformPoint(m_r1, pointInShell, m_t1);
  }

  bool ignored(int point) const { return m_settings.ignoredPoints && (*m_settings.ignoredPoints)[point] != 0; }

  /// The culling test of inner node `node` (see field_culling_bounds.h) on the part [tStart, tLimit] of the
  /// step (tLimit < 1: the earliest-contact search needs nothing later than its best contact).
  /// When it may collide, `outFirst` is a fraction before which no point below the node touches.
  bool nodeMayCollide(int node, double tStart, SegmentCcdResult& scratch, RigidCcdStats& stats, double& outFirst,
                      double tLimit = 1.0) const {
    outFirst = tStart;
    const Vec3& c = m_tree.center(node);
    const Vec3 cStart = startOf(c);
    const Vec3 c1 = endOf(c);
    const Vec3 c0 = tStart > 0.0 ? Vec3(cStart + tStart * (c1 - cStart)) : cStart;
    const double rho = m_tree.radius(node);
    // Slack against rounding: the points' segments are computed with different roundings than the centre's.
    // A field with jumps (a triangle set's slabs) can drop by `jump` more than its Lipschitz bound says, where
    // the node's path comes near one.
    const double jump = fieldJumpNear(m_field, m_bounds, c0, c1, rho);
    const double reach = m_bounds.lipschitz * rho * tolerance::kBoundGrowth + jump;
    const double sigmaNode = m_settings.sigma + reach;
    // The part of [c0, c1] up to tLimit, as a fraction of [c0, c1] (with a margin against rounding).
    const double reachFraction =
        tLimit >= 1.0 ? 1.0 : std::min(1.0, (tLimit - tStart) / (1.0 - tStart) + tolerance::kFractionSlack);
    if (m_bounds.bounded) {
      const Box3 grown(m_bounds.box.min() - Vec3::Constant(rho), m_bounds.box.max() + Vec3::Constant(rho));
      double enter = 0.0;
      if (!segmentMeetsBox(c0, c1, grown, enter)) return false;  // no point below can enter the box
      if (m_bounds.boundaryMin - reach <= m_settings.sigma &&
          !(detail::scalar_ops::boxContains(m_bounds.box, c0) && detail::scalar_ops::boxContains(m_bounds.box, c1))) {
        // The centre passes outside the box near a face low enough to touch: keep (conservative), but no point
        // below touches before the centre comes within rho of the box.
        if (enter > reachFraction) return false;
        outFirst = std::max(tStart, tStart + enter * (1.0 - tStart) - tolerance::kFractionSlack);
        return true;
      }
    }
    // Lipschitz early-out (short steps, the simulation case): phi along the segment stays above
    // phi(c0) - lipschitz * |c1 - c0|, on the part inside the box when c0 is (the box is convex).
    if (!m_bounds.bounded || detail::scalar_ops::boxContains(m_bounds.box, c0)) {
      const double lowest =
          m_field.distance(c0) - m_bounds.lipschitz * (c1 - c0).norm() * reachFraction * tolerance::kBoundGrowth - jump;
      if (lowest > sigmaNode) return false;
    }
    SegmentCcdSettings nodeSettings = m_node;
    nodeSettings.sigma = sigmaNode;
    nodeSettings.maxFraction = reachFraction;
    ++stats.segmentQueries;
    m_field.intersectSegment(c0, c1, nodeSettings, scratch);
    if (!scratch.hit()) return false;
    // Before the centre first reaches sigma + lipschitz * rho, no point below touches (the box-margin case
    // returned above). The margin keeps rounding on the safe side.
    outFirst = std::max(tStart, tStart + scratch.fraction * (1.0 - tStart) - tolerance::kFractionSlack);
    return true;
  }

  /// Can point `point` touch at or before fraction `tLimit`? (Exact roots on the segment's first part only: never
  /// false for a point whose full query touches by then.)
  bool pointMayTouchBy(int point, double tLimit, SegmentCcdResult& scratch, RigidCcdStats& stats) const {
    const Vec3& x = m_tree.shell().positions[point];
    SegmentCcdSettings settings = m_leaf;
    settings.mode = CcdMode::FirstHit;
    settings.method = CcdMethod::Exact;
    settings.maxFraction = std::min(1.0, tLimit + tolerance::kFractionSlack);
    ++stats.segmentQueries;
    m_field.intersectSegment(startOf(x), endOf(x), settings, scratch);
    return scratch.hit();
  }

  /// The query of one point; appends a contact when it touches. `phiAtEnd`: m_field.distance(endOf(x)) when the
  /// caller has it already (the coherent query's certificate of the leaf), spares the contact's end lookup.
  void queryPoint(int point, SegmentCcdResult& scratch, std::vector<PointContact>& outContacts, RigidCcdStats& stats,
                  const double* phiAtEnd = nullptr) const {
    const Vec3& x = m_tree.shell().positions[point];
    const Vec3 p0 = startOf(x);
    const Vec3 p1 = endOf(x);
    ++stats.segmentQueries;
    m_field.intersectSegment(p0, p1, m_leaf, scratch);
    if (!scratch.hit()) return;
    outContacts.emplace_back();
    PointContact& contact = outContacts.back();
    contact.point = point;
    contact.state = scratch.state;
    contact.fraction = scratch.fraction;
    contact.intervals = scratch.intervals;
    contact.depthAtEnd = (phiAtEnd != nullptr ? *phiAtEnd : m_field.distance(p1)) - m_settings.sigma;
    contact.fieldNormalInSdf = scratch.normal;
    contact.pointNormalInShell = m_tree.shell().normals[point];
  }

  /// Breadth-first traversal from the nodes in `current` (consumed); stops early when the frontier reaches
  /// `stopAt` nodes (0: never), leaving it in `current`.
  void traverse(std::vector<NodeTask>& current, std::vector<NodeTask>& next, SegmentCcdResult& scratch,
                std::vector<PointContact>& outContacts, RigidCcdStats& stats, std::size_t stopAt) const {
    const int* firstChild = m_tree.firstChildren().data();
    const int* childCount = m_tree.childCounts().data();
    while (!current.empty()) {
      if (stopAt > 0 && current.size() >= stopAt) return;
      next.clear();
      for (const NodeTask& task : current) {
        const int node = task.node;
        if (childCount[node] == 0) {
          const int point = m_tree.point(node);
          if (ignored(point)) continue;
          ++stats.nodesVisited;
          queryPoint(point, scratch, outContacts, stats);
          continue;
        }
        ++stats.nodesVisited;
        double first = 0.0;
        if (!nodeMayCollide(node, task.tStart, scratch, stats, first)) continue;
        for (int c = 0; c < childCount[node]; ++c) next.push_back({firstChild[node] + c, first});
      }
      current.swap(next);
    }
  }

  /// earliestOnly: keeps in `out.contacts` only the contacts at the smallest fraction seen so far (one of them
  /// with earliestOneContact). Once a contact is known, a point is first tested up to it only, and queried over
  /// the whole step (as the linear traversal does) only when it touches by then.
  void keepEarliest(int point, SegmentCcdResult& scratch, std::vector<PointContact>& candidate, bool& found,
                    double& best, RigidCcdResult& out) const {
    if (found && !pointMayTouchBy(point, best, scratch, out.stats)) return;
    candidate.clear();
    queryPoint(point, scratch, candidate, out.stats);
    if (candidate.empty()) return;
    PointContact& contact = candidate.front();
    if (!found || contact.fraction < best) {
      out.contacts.clear();
      best = contact.fraction;
      found = true;
    } else if (m_settings.earliestOneContact) {
      return;  // a tie adds nothing
    }
    if (contact.fraction == best) out.contacts.push_back(std::move(contact));
  }

  /// earliestOnly, tree: a quick search at the step's start for a point already in contact (bodies that start
  /// interpenetrated): a static depth-first descent culled by phi(centre) - L rho > sigma, one field lookup per
  /// node. A point found inside is queried as the linear traversal queries it and becomes the best contact, at
  /// fraction 0, so the search proper has nothing left to improve (one witness) or tests everything at
  /// fraction 0 only. Nothing else is recorded.
  bool findPointStartingInside(RigidCcdScratch& scratch, std::vector<PointContact>& candidate, bool& found,
                               double& best, RigidCcdResult& out) const {
    const int* firstChild = m_tree.firstChildren().data();
    const int* childCount = m_tree.childCounts().data();
    std::vector<NodeTask>& stack = scratch.next;
    stack.clear();
    stack.push_back({0, 0.0});
    while (!stack.empty()) {
      const int node = stack.back().node;
      stack.pop_back();
      const Vec3 c0 = startOf(m_tree.center(node));
      const double rho = m_tree.radius(node);
      const double reach =
          m_bounds.lipschitz * rho * tolerance::kBoundGrowth + fieldJumpNear(m_field, m_bounds, c0, c0, rho);
      if (m_bounds.bounded && !detail::scalar_ops::boxContains(m_bounds.box, c0)) {
        // Points below lie within rho of c0; inside the box phi >= boundaryMin - L rho there.
        if (detail::scalar_ops::distanceToBox(c0, m_bounds.box) > rho ||
            m_bounds.boundaryMin - reach > m_settings.sigma)
          continue;
      } else if (m_field.distance(c0) - reach > m_settings.sigma) {
        continue;
      }
      if (childCount[node] == 0) {
        const int point = m_tree.point(node);
        if (ignored(point)) continue;
        const Vec3 p0 = startOf(m_tree.shell().positions[point]);
        if ((m_bounds.bounded && !detail::scalar_ops::boxContains(m_bounds.box, p0)) ||
            m_field.distance(p0) > m_settings.sigma)
          continue;
        ++out.stats.nodesVisited;
        candidate.clear();
        queryPoint(point, scratch.segment, candidate, out.stats);  // the same query as the linear traversal's
        if (candidate.empty() || candidate.front().fraction != 0.0) continue;
        out.contacts.clear();
        out.contacts.push_back(std::move(candidate.front()));
        found = true;
        best = 0.0;
        return true;
      }
      for (int c = childCount[node] - 1; c >= 0; --c) stack.push_back({firstChild[node] + c, 0.0});
    }
    return false;
  }

  /// earliestOnly: can nothing starting at `bound` improve on the best contact?
  bool cannotImprove(bool found, double best, double bound) const {
    return found && (bound > best || (m_settings.earliestOneContact && bound >= best));
  }

  /// earliestOnly, serial. Tree: depth-first branch and bound on the nodes' lower bounds (the fraction before
  /// which no point below touches); a node whose bound exceeds the best contact found is pruned. Leaves run the same
  /// point query as the linear traversal, so the fraction is bit-identical to the minimum over the linear contacts.
  /// Ties (bound == best) are kept, so every point at the earliest fraction is returned.
  void runEarliest(RigidCcdResult& out) const {
    RigidCcdScratch& scratch = rigidCcdScratch();
    std::vector<PointContact> candidate;
    bool found = false;
    double best = 1.0;
    if (!m_settings.useTree) {
      for (int p = 0; p < m_tree.pointCount(); ++p) {
        if (cannotImprove(found, best, 0.0)) break;  // one contact at fraction 0 is enough
        if (!ignored(p)) keepEarliest(p, scratch.segment, candidate, found, best, out);
      }
    } else {
      const int* firstChild = m_tree.firstChildren().data();
      const int* childCount = m_tree.childCounts().data();
      if (findPointStartingInside(scratch, candidate, found, best, out)) {
        if (m_settings.earliestOneContact) {
          out.firstFraction = 0.0;
          return;
        }
        out.contacts.clear();  // the search below collects every point at fraction 0, this one included
      }
      // Depth-first branch and bound: a descent reaches a first contact quickly, and every later node and point
      // is tested only up to the best contact so far, which makes their walks short. (On Table 3 it beats a
      // best-first search on the nodes' bounds: that one tests fewer nodes, but most of them before a good bound
      // is known.)
      std::vector<NodeTask>& stack = scratch.current;
      stack.clear();
      stack.push_back({0, 0.0});
      while (!stack.empty()) {
        const NodeTask task = stack.back();
        stack.pop_back();
        if (cannotImprove(found, best, task.tStart)) continue;
        const int node = task.node;
        if (childCount[node] == 0) {
          const int point = m_tree.point(node);
          if (ignored(point)) continue;
          ++out.stats.nodesVisited;
          keepEarliest(point, scratch.segment, candidate, found, best, out);
          continue;
        }
        ++out.stats.nodesVisited;
        double first = 0.0;
        if (!nodeMayCollide(node, task.tStart, scratch.segment, out.stats, first, found ? best : 1.0)) continue;
        if (cannotImprove(found, best, first)) continue;
        for (int c = childCount[node] - 1; c >= 0; --c) stack.push_back({firstChild[node] + c, first});  // first on top
      }
    }
    std::sort(out.contacts.begin(), out.contacts.end(),
              [](const PointContact& a, const PointContact& b) { return a.point < b.point; });
    if (found) out.firstFraction = best;
  }

  void run(RigidCcdResult& out) const {
    if (m_settings.earliestOnly) {
      runEarliest(out);
      return;
    }
    const int threads = m_settings.threads <= 0 ? defaultThreadCount() : m_settings.threads;
    RigidCcdScratch& scratch = rigidCcdScratch();
    if (m_settings.useTree) {
      scratch.current.clear();
      scratch.current.push_back({0, 0.0});
      const std::size_t split = threads > 1 ? static_cast<std::size_t>(16 * threads) : 0;
      traverse(scratch.current, scratch.next, scratch.segment, out.contacts, out.stats, split);
      if (!scratch.current.empty()) {
        scratch.frontier.swap(scratch.current);
        runParallel(scratch.frontier, threads, out);
      }
    } else if (threads <= 1) {
      for (int p = 0; p < m_tree.pointCount(); ++p) {
        if (!ignored(p)) queryPoint(p, scratch.segment, out.contacts, out.stats);
      }
    } else {
      scratch.frontier.clear();
      for (int p = 0; p < m_tree.pointCount(); ++p) {
        if (!ignored(p)) scratch.frontier.push_back({p, 0.0});
      }
      runParallel(scratch.frontier, threads, out);
    }
    std::sort(out.contacts.begin(), out.contacts.end(),
              [](const PointContact& a, const PointContact& b) { return a.point < b.point; });
    for (const auto& contact : out.contacts) out.firstFraction = std::min(out.firstFraction, contact.fraction);
  }

 private:
  // Tree mode: `items` are frontier nodes, each traversed to the bottom by one task. Linear mode: points.
  void runParallel(const std::vector<NodeTask>& items, int threads, RigidCcdResult& out) const {
    constexpr std::size_t kLinearBlock = 256;
    const bool tree = m_settings.useTree;
    const std::size_t tasks = tree ? items.size() : (items.size() + kLinearBlock - 1) / kLinearBlock;
    std::vector<std::vector<PointContact>> contacts(static_cast<std::size_t>(threads));
    std::vector<RigidCcdStats> stats(static_cast<std::size_t>(threads));
    parallelFor(tasks, threads, [&](std::size_t task, int thread) {
      RigidCcdScratch& local = rigidCcdScratch();
      if (tree) {
        local.current.clear();
        local.current.push_back(items[task]);
        traverse(local.current, local.next, local.segment, contacts[thread], stats[thread], 0);
      } else {
        const std::size_t end = std::min(items.size(), (task + 1) * kLinearBlock);
        for (std::size_t n = task * kLinearBlock; n < end; ++n) {
          queryPoint(items[n].node, local.segment, contacts[thread], stats[thread]);
        }
      }
    });
    for (int t = 0; t < threads; ++t) {
      out.stats.nodesVisited += stats[t].nodesVisited;
      out.stats.segmentQueries += stats[t].segmentQueries;
      for (auto& c : contacts[t]) out.contacts.push_back(std::move(c));
    }
  }

  const PointTree& m_tree;
  const Field& m_field;
  const RigidCcdSettings& m_settings;
  Mat3 m_r0;
  Mat3 m_r1;
  Vec3 m_t0;
  Vec3 m_t1;
  FieldCullingBounds m_bounds;
  SegmentCcdSettings m_leaf;
  SegmentCcdSettings m_node;
};

}  // namespace detail
}  // namespace sdfccd
