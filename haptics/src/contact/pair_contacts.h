/// @file
/// @brief PairContacts: one obstacle pair's contact state in the constraint method (god_object.h, steps 5 and 6),
/// shared by both kinds of pair (obstacle_pair.h; internal to the haptics library).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "contact/obstacle_pair.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/ccd/segment_ccd.h"
#include "sdfccd/haptics/god_object.h"
#include "sdfccd/math_types.h"
#include "sdfccd/shell/point_tree.h"

namespace sdfccd::haptics {

/// The guard CCD of the constraint method (god_object.h): the points in contact last cycle (`notInContact` is 0 for
/// them; `contactCount` of them) may slide but not sink below slideFloor over the move sdfStart -> sdfEnd of the
/// shell in the field's frame. A point already under the floor (rounding, the chord of a rotation) starts inside and
/// must not freeze the god-object: it is held at its own depth less sinkTolerance. Returns the earliest fraction
/// (1: none).
template <class Field>
double guardFraction(const PointTree& tree, const Field& field, const Rigid& sdfStart, const Rigid& sdfEnd,
                     const GodObjectSettings& s, const std::vector<std::uint8_t>& notInContact,
                     std::size_t contactCount, RigidCcdResult& ccdScratch, SegmentCcdResult& segmentScratch,
                     GodObjectStepResult& out) {
  RigidCcdSettings ccd = constraintCcdSettings(s, s.slideFloor);
  ccd.ignoredPoints = &notInContact;
  // Few contacts: visiting them point by point beats re-testing every inner node of the tree.
  ccd.useTree = contactCount * 16 > static_cast<std::size_t>(tree.pointCount());
  rigidCcd(tree, field, sdfStart, sdfEnd, ccd, ccdScratch);
  out.segmentQueries += ccdScratch.stats.segmentQueries;
  double fraction = 1.0;
  SegmentCcdSettings sink;
  sink.mode = CcdMode::FirstHit;
  sink.method = s.ccdMethod;
  sink.octree = s.octree;
  for (const PointContact& c : ccdScratch.contacts) {
    if (c.state == SegmentState::Hit) {
      fraction = std::min(fraction, c.fraction);
    } else if (c.state == SegmentState::StartsInside) {
      const Vec3& x = tree.shell().positions[static_cast<std::size_t>(c.point)];
      const Vec3 p0 = sdfStart * x;
      const Vec3 p1 = sdfEnd * x;
      sink.sigma = std::min(field.distance(p0), s.slideFloor) - s.sinkTolerance;
      field.intersectSegment(p0, p1, sink, segmentScratch);
      ++out.segmentQueries;
      if (segmentScratch.state == SegmentState::Hit) fraction = std::min(fraction, segmentScratch.fraction);
    }
  }
  return fraction;
}

/// The shell points of one pair in contact, the flags its CCD reads, the candidates of the next contact set, and the
/// scratch of the pair's queries.
class PairContacts {
 public:
  /// Sized for a shell of `points` points, none in contact.
  explicit PairContacts(std::size_t points) : m_inContact(points, 0), m_notInContact(points, 1) {}

  /// Per shell point: in contact last cycle (the CCD ignores them, the paper's sliding remedy).
  const std::vector<std::uint8_t>& inContact() const { return m_inContact; }
  /// The points in contact now, ascending.
  const std::vector<int>& points() const { return m_points; }
  RigidCcdResult& ccd() { return m_ccd; }

  /// The points the pair's last query (ccd()) reported become candidates.
  void addCandidates() {
    for (const PointContact& c : m_ccd.contacts) m_candidates.push_back(c.point);
  }

  /// Step 5: the CCD `ccd` (its level set, ignore list and traversal set by the caller) of the shell over the move
  /// sdfStart -> sdfEnd in the field's frame, its points made candidates, then the guard CCD on the points in
  /// contact. Returns the earliest contact fraction (1: none).
  template <class Field>
  double continuousFraction(const PointTree& tree, const Field& field, const Rigid& sdfStart, const Rigid& sdfEnd,
                            const GodObjectSettings& s, const RigidCcdSettings& ccd, GodObjectStepResult& out) {
    rigidCcd(tree, field, sdfStart, sdfEnd, ccd, m_ccd);
    out.segmentQueries += m_ccd.stats.segmentQueries;
    double fraction = 1.0;
    for (const PointContact& c : m_ccd.contacts) {
      fraction = std::min(fraction, c.fraction);
      m_candidates.push_back(c.point);
    }
    if (s.ignoreContactPoints && s.guardIgnoredPoints && !m_points.empty())
      fraction = std::min(fraction, guardFraction(tree, field, sdfStart, sdfEnd, s, m_notInContact, m_points.size(),
                                                  m_ccd, m_segment, out));
    return fraction;
  }

  /// Step 6: the contact set at the new pose. Every candidate and last contact, in ascending order, where
  /// `contactAt(p, c)` makes contact `c` of point p (false: not in contact), is appended to `next`; the points that
  /// were not in contact before count as new.
  template <class ContactAt>
  void update(const ContactAt& contactAt, std::vector<GodObjectContact>& next, GodObjectStepResult& out) {
    m_candidates.insert(m_candidates.end(), m_points.begin(), m_points.end());
    std::sort(m_candidates.begin(), m_candidates.end());
    m_candidates.erase(std::unique(m_candidates.begin(), m_candidates.end()), m_candidates.end());
    m_kept.clear();
    for (const int p : m_candidates) {
      GodObjectContact c;
      if (!contactAt(p, c)) continue;
      if (!m_inContact[static_cast<std::size_t>(p)]) ++out.newContacts;
      m_kept.push_back(p);
      next.push_back(c);
    }
    for (const int p : m_points) {
      m_inContact[static_cast<std::size_t>(p)] = 0;
      m_notInContact[static_cast<std::size_t>(p)] = 1;
    }
    m_points.swap(m_kept);
    for (const int p : m_points) {
      m_inContact[static_cast<std::size_t>(p)] = 1;
      m_notInContact[static_cast<std::size_t>(p)] = 0;
    }
    m_candidates.clear();
  }

 private:
  std::vector<std::uint8_t> m_inContact;
  std::vector<std::uint8_t> m_notInContact;  // the complement (the guard CCD's ignore list)
  std::vector<int> m_points;
  std::vector<int> m_candidates;
  std::vector<int> m_kept;
  RigidCcdResult m_ccd;
  SegmentCcdResult m_segment;
};

}  // namespace sdfccd::haptics
