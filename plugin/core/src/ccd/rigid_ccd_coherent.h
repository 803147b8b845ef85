/// @file
/// @brief detail::runCoherent: the every-contact query started from the last query's front (see
/// rigid_ccd_coherence.h). Private to the core: rigid_ccd.cpp instantiates it with RigidCcdQuery.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "ccd/rigid_ccd_axis_certificate.h"
#include "ccd/rigid_ccd_query.h"
#include "sdfccd/ccd/rigid_ccd_coherence.h"
#include "sdfccd/field/analytic_fields.h"

namespace sdfccd {
namespace detail {

/// Poses kept before the unused ones are dropped.
constexpr std::size_t kCoherencePoses = 8;
/// Front nodes kept from the last query try to ascend once every this many queries (nodes re-tested this
/// query try at once): the check costs as much as the certificate's, and parents rarely qualify step to step.
constexpr std::uint64_t kAscentPeriod = 8;

/// The tables of `tree` (parents, reach from the shell origin), shared by every history of that tree: built on
/// the first request, kept while a history holds them (rigid_ccd.cpp; thread safe).
std::shared_ptr<const RigidCcdCoherence::TreeTables> rigidCcdTreeTables(const PointTree& tree);

/// ||R_a - R_b||_F, in plain scalar code that inlines: Eigen's reduction over the blocks of the 4x4 matrices is an
/// out-of-line call, on the whole-front test that a pile of bodies runs for most pairs (a bound with the
/// certificates' slack: its rounding need not match any other evaluation).
inline double rotationDistance(const Rigid& a, const Rigid& b) {
  double sum = 0.0;
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) {
      const double d = a.linear()(r, c) - b.linear()(r, c);
      sum += d * d;
    }
  }
  return std::sqrt(sum);
}

/// Every entry of the pose finite: matrix().allFinite(), the same answer, in scalar code (finiteValues) that
/// inlines where Eigen's does not, on the whole-front test that most pairs of a pile end at (coherentFrontClear).
inline bool finitePose(const Rigid& pose) {
  return finiteValues(pose.data(), 16);
}

/// |t_a - t_b|.
inline double translationDistance(const Rigid& a, const Rigid& b) {
  const double x = a.translation().x() - b.translation().x();
  const double y = a.translation().y() - b.translation().y();
  const double z = a.translation().z() - b.translation().z();
  return std::sqrt(x * x + y * y + z * z);
}

/// How far the shell's points may have moved since pose `p`, in the step [start, end]: the largest Frobenius
/// norm of the rotation change (times a point's distance from the shell origin) and of the translation change.
struct PoseMotion {
  double rotation = 0.0;
  double translation = 0.0;
};
inline PoseMotion motionSince(const Rigid& p, const Rigid& start, const Rigid& end) {
  return {std::max(rotationDistance(start, p), rotationDistance(end, p)),
          std::max(translationDistance(start, p), translationDistance(end, p))};
}

/// What keys a history to its field: a field with an instance id (instance_id.h) by that id; the analytic plane
/// and box by their values (a new object with the same values is the same field, wherever it lives: Bullet's
/// ground is built per step); any other field has no key (id 0: no history). The ids of the value keys lie far
/// above any instance id (a counter from 1).
struct FieldKey {
  std::uint64_t id = 0;
  std::array<double, 4> value{};
};
constexpr std::uint64_t kPlaneKeyId = ~std::uint64_t(0);
constexpr std::uint64_t kBoxKeyId = ~std::uint64_t(0) - 1;

template <class Field, class = void>
struct HasInstanceId : std::false_type {};
template <class Field>
struct HasInstanceId<Field, std::void_t<decltype(std::declval<const Field&>().instanceId())>> : std::true_type {};

template <class Field>
FieldKey fieldKey(const Field& field) {
  if constexpr (HasInstanceId<Field>::value) {
    return {field.instanceId(), {}};
  } else if constexpr (std::is_same_v<Field, PlaneField>) {
    return {kPlaneKeyId, {field.normal().x(), field.normal().y(), field.normal().z(), field.offset()}};
  } else if constexpr (std::is_same_v<Field, BoxField>) {
    return {kBoxKeyId, {field.halfExtents().x(), field.halfExtents().y(), field.halfExtents().z(), 0.0}};
  } else {
    return {};
  }
}
/// Can a history be keyed to this field type (else the query runs fresh and forgets the history)?
template <class Field>
constexpr bool kCoherentField =
    HasInstanceId<Field>::value || std::is_same_v<Field, PlaneField> || std::is_same_v<Field, BoxField>;

/// Is `history` keyed to these inputs (else the query starts afresh)?
template <class Field>
bool coherenceMatches(const RigidCcdCoherence& c, const PointTree& tree, const Field& field, double sigma,
                      double lipschitz) {
  const FieldKey key = fieldKey(field);
  return c.treeId == tree.instanceId() && c.fieldId == key.id && c.fieldValue == key.value &&
         c.nodeCount == tree.nodeCount() && c.sigma == sigma && c.lipschitz == lipschitz;
}

/// The whole-front test: true when every front entry's certificate holds for the step [start, end], checked once
/// against the newest kept pose r on the front's folded bound (RigidCcdCoherence::FrontBound) instead of entry by
/// entry and pose by pose. An entry e at pose k moves at most rot_k reach(e) + trans_k, and by the triangle
/// inequality rot_k <= rot_r + ||R_r - R_k||_F and trans_k <= trans_r + |t_r - t_k|; the fold takes the second
/// terms off each entry's slack, so with maxReach >= reach(e) and minSlack <= room(e) / kBoundGrowth - radius(e) -
/// (||R_r - R_k||_F reach(e) + |t_r - t_k|),
///   (rotation_r maxReach + translation_r) kBoundGrowth < minSlack
/// implies (radius(e) + moved(e)) kBoundGrowth < room(e), the entry's own test (CoherentQuery::certified); the
/// factor kBoundGrowth on the left keeps the folding's rounding (relative 1e-16) far inside that test's slack.
/// Then no point can touch during the step and the query's answer is empty. One pose's motion instead of one per
/// kept pose: the fold is slightly looser only for a shell that came back near an older pose. False for a
/// non-finite pose (the full query reports it).
template <class Field>
bool coherentFrontClear(const RigidCcdCoherence& c, const PointTree& tree, const Field& field,
                        const RigidCcdSettings& settings, const Rigid& start, const Rigid& end) {
  if (!c.frontCertified || c.front.empty() || c.poses.empty()) return false;
  if (!coherenceMatches(c, tree, field, settings.sigma, fieldCullingBounds(field).lipschitz)) return false;
  if (!finitePose(start) || !finitePose(end) || !std::isfinite(settings.sigma)) return false;
  // The newest kept pose is the last full query's end: its copy in the history itself (lastEnd) spares a cache
  // miss on the poses' buffer in a world of many pairs.
  const PoseMotion m = motionSince(c.lastEndValid ? c.lastEnd : c.poses.back(), start, end);
  return (m.rotation * c.frontBound.maxReach + m.translation) * tolerance::kBoundGrowth < c.frontBound.minSlack;
}

template <class Field>
class CoherentQuery {
 public:
  CoherentQuery(const RigidCcdQuery<Field>& query, const PointTree& tree, const Field& field,
                const RigidCcdSettings& settings, const Rigid& start, const Rigid& end, RigidCcdCoherence& cache)
      : m_query(query),
        m_tree(tree),
        m_field(field),
        m_settings(settings),
        m_cache(cache),
        m_scratch(rigidCcdScratch()),
        m_segment(m_scratch.segment),
        m_end(end) {
    m_bounds = fieldCullingBounds(field);
    prepareCache(start, end);
    m_axis = AxisCertificates<Field>(cache, field, start, end, m_reach[0], startsAtLastEnd(start));
  }

  void run(RigidCcdResult& out) {
    std::vector<RigidCcdCoherence::Entry>& next = m_scratch.front;
    next.clear();
    m_cache.frontCertified = false;  // until the new front is folded (an exception leaves the fast path off)
    m_cache.lastEndValid = false;    // until rememberEnd (likewise)
    const bool ascend = m_cache.queries++ % kAscentPeriod == 0;
    for (const RigidCcdCoherence::Entry& entry : m_cache.front) {
      if (certified(entry, 1.0)) {
        ++out.stats.certified;
        emit(entry, next, ascend);
      } else {
        descend(entry.node, out, next);
      }
    }
    // Copied, not swapped: the history's buffer was just read (warm), the thread's is reused by its next query.
    m_cache.front.assign(next.begin(), next.end());
    const bool compacted = compactPoses();
    rememberEnd(m_end, compacted ? &m_scratch.remap : nullptr);
    m_cache.frontBound = m_fold;
    m_cache.frontCertified = m_foldComplete && !m_cache.front.empty();
    std::sort(out.contacts.begin(), out.contacts.end(),
              [](const PointContact& a, const PointContact& b) { return a.point < b.point; });
    for (const auto& contact : out.contacts) out.firstFraction = std::min(out.firstFraction, contact.fraction);
  }

 private:
  /// Keys the cache to this tree, field, sigma and bound; adds this step's end pose (new certificates' pose)
  /// and each kept pose's largest distance to the step's two poses.
  void prepareCache(const Rigid& start, const Rigid& end) {
    RigidCcdCoherence& c = m_cache;
    if (!coherenceMatches(c, m_tree, m_field, m_settings.sigma, m_bounds.lipschitz)) {
      c.reset();
      c.treeId = m_tree.instanceId();
      const FieldKey key = fieldKey(m_field);
      c.fieldId = key.id;
      c.fieldValue = key.value;
      c.nodeCount = m_tree.nodeCount();
      c.sigma = m_settings.sigma;
      c.lipschitz = m_bounds.lipschitz;
      c.tables = rigidCcdTreeTables(m_tree);
      c.front.push_back({0, -1, 0.0, 0.0, RigidCcdCoherence::Kind::None});
    }
    m_parent = c.tables->parent.data();
    m_reach = c.tables->reachFromOrigin.data();
    c.poses.push_back(end);
    m_endPose = static_cast<int>(c.poses.size()) - 1;
    m_rotation.resize(c.poses.size());
    m_translation.resize(c.poses.size());
    m_rotationToEnd.resize(c.poses.size());
    m_translationToEnd.resize(c.poses.size());
    // The older poses' distances to the start pose: the last query's to its end when this one starts there.
    const std::size_t known = startsAtLastEnd(start) ? c.lastRotationToEnd.size() : 0;
    // Each pose's distance to the end pose is one half of its motion and what the fold (foldEntry) takes off.
    for (std::size_t k = 0; k < c.poses.size(); ++k) {
      const Rigid& p = c.poses[k];
      m_rotationToEnd[k] = rotationDistance(end, p);
      m_translationToEnd[k] = translationDistance(end, p);
      const double rotationFromStart = k < known ? c.lastRotationToEnd[k] : rotationDistance(start, p);
      const double translationFromStart = k < known ? c.lastTranslationToEnd[k] : translationDistance(start, p);
      m_rotation[k] = std::max(rotationFromStart, m_rotationToEnd[k]);
      m_translation[k] = std::max(translationFromStart, m_translationToEnd[k]);
    }
  }

  /// Does this query start exactly where the last one ended, with that query's distances kept for every pose but
  /// the one just added (the end pose)?
  bool startsAtLastEnd(const Rigid& start) const {
    const RigidCcdCoherence& c = m_cache;
    return c.lastEndValid && c.lastRotationToEnd.size() + 1 == c.poses.size() &&
           c.lastTranslationToEnd.size() == c.lastRotationToEnd.size() && start.matrix() == c.lastEnd.matrix();
  }

  /// Keeps the kept poses' distances to this query's end pose for the next query (startsAtLastEnd), in the
  /// poses' order after compaction (`remap`: old index to new, -1 dropped; null when none ran).
  void rememberEnd(const Rigid& end, const std::vector<int>* remap) {
    RigidCcdCoherence& c = m_cache;
    c.lastEnd = end;
    c.lastEndValid = true;
    const std::size_t n = c.poses.size();
    c.lastRotationToEnd.resize(n);
    c.lastTranslationToEnd.resize(n);
    const std::vector<Vec3>* axisToEnd = m_axis.toEnd();
    c.lastAxisToEnd.resize(axisToEnd != nullptr ? 2 * n : 0);
    for (std::size_t k = 0; k < m_rotationToEnd.size(); ++k) {
      const int to = remap != nullptr ? (*remap)[k] : static_cast<int>(k);
      if (to < 0) continue;
      const std::size_t j = static_cast<std::size_t>(to);
      c.lastRotationToEnd[j] = m_rotationToEnd[k];
      c.lastTranslationToEnd[j] = m_translationToEnd[k];
      if (axisToEnd != nullptr) {
        c.lastAxisToEnd[2 * j] = (*axisToEnd)[2 * k];
        c.lastAxisToEnd[2 * j + 1] = (*axisToEnd)[2 * k + 1];
      }
    }
  }

  /// Can the node's certificate rule out a contact during this step? `headroom` > 1 asks for room to spare
  /// (ascent: a parent that would fail at once is not worth it).
  bool certified(const RigidCcdCoherence::Entry& e, double headroom) const {
    if (e.kind == RigidCcdCoherence::Kind::None) return false;
    const double moved = m_rotation[e.pose] * m_reach[e.node] + m_translation[e.pose];
    if ((m_tree.radius(e.node) + headroom * moved) * tolerance::kBoundGrowth < e.room) return true;
    return m_axis.holds(e, m_tree.radius(e.node), m_reach[e.node], m_settings.sigma, headroom);
  }

  /// The distance the node's points may reach from its centre `c1` at the certificate's pose without touching
  /// (`room` of the entry; the same for every node of that centre), with slack against rounding of the same
  /// relative size as the traversal's, on the magnitudes involved: the clearance and sigma, and the coordinates
  /// (the points' positions and the field's value round relative to them: far from the origin an unbounded
  /// field's clearance can be small beside them).
  double roomOf(const RigidCcdCoherence::Entry& e, const Vec3& c1) const {
    constexpr double eps = tolerance::kRelativeSlack;
    const double coordinates = eps * (c1.norm() + m_reach[0]);  // the root's reach: any point's (ascent too)
    if (e.kind == RigidCcdCoherence::Kind::Box) return e.clearance * (1.0 - eps) - coordinates;
    const double margin =
        e.clearance - m_settings.sigma - eps * (std::abs(e.clearance) + std::abs(m_settings.sigma)) - coordinates;
    const double room = margin / m_bounds.lipschitz * (1.0 - eps);
    // A field with jumps: the room holds as it is when no jump is within it of the certificate's centre;
    // otherwise the jump comes off the margin (a smaller room, so the same check still covers it).
    const double jump = room > 0.0 ? fieldJumpNear(m_field, m_bounds, c1, c1, room) : 0.0;
    if (jump == 0.0) return room;
    return (margin - jump * (1.0 + eps)) / m_bounds.lipschitz * (1.0 - eps);
  }

  /// A certificate for `node` at this step's end pose (whether it is worth anything, certified() decides each
  /// step; None only for a non-finite value).
  RigidCcdCoherence::Entry certify(int node) const {
    RigidCcdCoherence::Entry e{node, m_endPose, 0.0, 0.0, RigidCcdCoherence::Kind::None};
    const Vec3 c1 = m_query.endOf(m_tree.center(node));
    if (m_bounds.bounded && !detail::scalar_ops::boxContains(m_bounds.box, c1)) {
      e.kind = RigidCcdCoherence::Kind::Box;
      e.clearance = detail::scalar_ops::distanceToBox(c1, m_bounds.box);
    } else {
      e.kind = RigidCcdCoherence::Kind::Phi;
      e.clearance = m_field.distance(c1);
      e.block = m_axis.blockOf(c1);
    }
    if (!std::isfinite(e.clearance)) e.kind = RigidCcdCoherence::Kind::None;
    e.room = roomOf(e, c1);
    return e;
  }

  /// The fresh traversal below `root` (depth first, so the new front stays in tree order): inner nodes by the
  /// fresh culling test, leaves by the same point query.
  void descend(int root, RigidCcdResult& out, std::vector<RigidCcdCoherence::Entry>& next) {
    std::vector<int>& stack = m_scratch.stack;
    stack.clear();
    stack.push_back(root);
    while (!stack.empty()) {
      const int node = stack.back();
      stack.pop_back();
      if (m_tree.isLeaf(node)) {
        const int point = m_tree.point(node);
        if (m_query.ignored(point)) {
          emit({node, -1, 0.0, 0.0, RigidCcdCoherence::Kind::None}, next);  // tested again when no longer ignored
          continue;
        }
        ++out.stats.nodesVisited;
        // A fresh certificate at this step's end pose rules the point out when its step is shorter than its
        // clearance (one lookup instead of the segment walk; the same Lipschitz argument as a kept one).
        const RigidCcdCoherence::Entry e = certify(node);
        if (certified(e, 1.0)) {
          emit(e, next);
          continue;
        }
        // The certificate looked phi up at the centre's end position, and a node's centre is its point, copied
        // (PointTree::center): that is the contact's phi at the end (queryPoint's endOf(x)), not looked up again.
        const bool phiKnown = e.kind == RigidCcdCoherence::Kind::Phi;
        const std::size_t before = out.contacts.size();
        m_query.queryPoint(point, m_segment, out.contacts, out.stats, phiKnown ? &e.clearance : nullptr);
        if (out.contacts.size() > before) {
          emit({node, -1, 0.0, 0.0, RigidCcdCoherence::Kind::None}, next);
        } else {
          emit(e, next);
        }
        continue;
      }
      ++out.stats.nodesVisited;
      const RigidCcdCoherence::Entry e = certify(node);  // as for a point: may spare the segment test
      double first = 0.0;
      if (certified(e, 1.0) || !m_query.nodeMayCollide(node, 0.0, m_segment, out.stats, first)) {
        emit(e, next);
        continue;
      }
      for (int c = m_tree.childCount(node) - 1; c >= 0; --c) stack.push_back(m_tree.firstChild(node) + c);
    }
  }

  /// Appends `e` to the new front, then replaces complete certified sibling groups at its end by their parent
  /// while the parent's certificate (its first child's) holds with room to spare.
  void emit(const RigidCcdCoherence::Entry& e, std::vector<RigidCcdCoherence::Entry>& next, bool ascend = true) {
    next.push_back(e);
    foldEntry(e);
    while (ascend) {
      const int node = next.back().node;
      const int parent = m_parent[node];
      if (parent < 0) return;
      const int first = m_tree.firstChild(parent);
      const int count = m_tree.childCount(parent);
      if (node != first + count - 1 || next.size() < static_cast<std::size_t>(count)) return;
      const std::size_t begin = next.size() - static_cast<std::size_t>(count);
      for (int k = 0; k < count; ++k) {
        const RigidCcdCoherence::Entry& sibling = next[begin + static_cast<std::size_t>(k)];
        if (sibling.node != first + k || sibling.kind == RigidCcdCoherence::Kind::None) return;
      }
      if (m_tree.center(parent) != m_tree.center(first)) return;
      RigidCcdCoherence::Entry up = next[begin];  // the parent's centre is its first child's
      up.node = parent;
      if (!certified(up, 2.0)) return;
      next.resize(begin);
      next.push_back(up);
      foldEntry(up);
    }
  }

  /// Folds `e` into the new front's bound at this step's end pose (the newest kept: compactPoses keeps it) for
  /// coherentFrontClear: its reach, and its slack less the motion from its certificate's pose to the end pose.
  /// Every entry pushed onto the new front is folded, also the sibling groups the ascent then replaces by their
  /// parent: a bound over more entries is only more conservative, and it costs no second pass over the front.
  void foldEntry(const RigidCcdCoherence::Entry& e) {
    if (!m_foldComplete) return;  // a contact or an ignored point is on the front: no bound (most full queries)
    if (e.kind == RigidCcdCoherence::Kind::None || e.pose < 0) {
      m_foldComplete = false;
      return;
    }
    const std::size_t k = static_cast<std::size_t>(e.pose);
    const double reach = m_reach[e.node];
    const double slack =
        e.room / tolerance::kBoundGrowth - m_tree.radius(e.node) - (m_rotationToEnd[k] * reach + m_translationToEnd[k]);
    if (m_foldEmpty) {
      m_fold = {reach, slack};
      m_foldEmpty = false;
    } else {
      m_fold.maxReach = std::max(m_fold.maxReach, reach);
      m_fold.minSlack = std::min(m_fold.minSlack, slack);
    }
  }

  /// Once there are many poses: moves the older half's certificates to the end pose and drops the poses no
  /// front entry refers to.
  bool compactPoses() {
    RigidCcdCoherence& c = m_cache;
    // Not before kCoherencePoses, nor before half as many new poses as that came since the last compaction: axis
    // certificates keep their poses, and deep in a hole they may keep many (a compaction walks the whole front).
    if (c.poses.size() < kCoherencePoses || c.poses.size() < c.posesAfterCompaction + kCoherencePoses / 2) return false;
    // In place, in the cache's buffers: this runs on most queries of a long contact (allocation-free).
    std::vector<int>& remap = m_scratch.remap;
    remap.assign(c.poses.size(), -1);
    // Certificates at the older half of the poses move to the end pose, so that the kept poses (one motion each
    // per query, prepareCache) stay few: by the triangle inequality a certificate at pose k holds at the end
    // pose with its room less the motion from k to the end, rotation times the root's reach (which bounds every
    // point's distance from the shell origin: the room stays the same for every node of a centre, as the ascent
    // takes it) plus translation, grown against rounding.
    const std::size_t migrateBelow = c.poses.size() / 2;
    const double rootReach = m_reach[0];
    for (auto& e : c.front) {
      if (e.pose < 0) continue;
      const std::size_t k = static_cast<std::size_t>(e.pose);
      // An axis certificate (block >= 0) charges the motion since its own pose from its clearance: it stays.
      if (k < migrateBelow && e.block < 0) {
        e.room -= (m_rotationToEnd[k] * rootReach + m_translationToEnd[k]) * tolerance::kBoundGrowth;
        e.pose = m_endPose;
      } else {
        remap[k] = 0;
      }
    }
    remap[static_cast<std::size_t>(m_endPose)] = 0;  // the whole-front bound's pose: kept, and stays the newest
    std::size_t kept = 0;
    for (std::size_t k = 0; k < c.poses.size(); ++k) {
      if (remap[k] < 0) continue;
      remap[k] = static_cast<int>(kept);
      if (kept != k) c.poses[kept] = c.poses[k];
      ++kept;
    }
    c.poses.resize(kept);
    for (auto& e : c.front) {
      if (e.pose >= 0) e.pose = remap[static_cast<std::size_t>(e.pose)];
    }
    c.posesAfterCompaction = kept;
    return true;
  }

  const RigidCcdQuery<Field>& m_query;
  const PointTree& m_tree;
  const Field& m_field;
  const RigidCcdSettings& m_settings;
  RigidCcdCoherence& m_cache;
  FieldCullingBounds m_bounds;
  const int* m_parent = nullptr;  // the shared tree tables (RigidCcdCoherence::TreeTables)
  const double* m_reach = nullptr;
  int m_endPose = -1;
  AxisCertificates<Field> m_axis;                                  // off unless the history asks for axis certificates
  RigidCcdScratch& m_scratch;                                      // this thread's buffers (rigid_ccd_query.h)
  std::vector<double>& m_rotation = m_scratch.rotation;            // per kept pose: largest ||R - R_k||_F over the
  std::vector<double>& m_translation = m_scratch.translation;      // step's two poses, and largest |t - t_k|
  std::vector<double>& m_rotationToEnd = m_scratch.rotationToEnd;  // per kept pose: ||R_end - R_k||_F and
  std::vector<double>& m_translationToEnd = m_scratch.translationToEnd;  // |t_end - t_k|
  RigidCcdCoherence::FrontBound m_fold;                                  // the new front's bound (foldEntry)
  bool m_foldEmpty = true;
  bool m_foldComplete = true;  // every entry folded carries a certificate
  SegmentCcdResult& m_segment;
  Rigid m_end;  // the step's end pose (rememberEnd)
};

}  // namespace detail
}  // namespace sdfccd
