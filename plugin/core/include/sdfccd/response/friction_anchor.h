/// @file
/// @brief Static friction that holds: an elastic–plastic (stick–slip) Coulomb anchor per shell point
/// (docs/design/contact-response.md, static friction; beyond the paper, whose Section 4.1 friction is regularized
/// and creeps).
///
/// @details Each shell point in contact is tied to an anchor, a point fixed in the field body's frame where the
/// point first touched. At a sample the tangential stretch s (point minus anchor, normal part removed) gives
/// the force F_t = -k_t s - c_t v_t, capped at |F_t| <= mu F_n (Coulomb; tangentialForce()). At the end of
/// the step an anchor whose elastic force k_t |s| exceeds mu F_n slips: it is dragged after the point until
/// k_t |s| = mu F_n (slipAnchor()). Below the cap it never moves, so a held point does not creep.
///
/// The anchors of one pair and role live in a FrictionAnchorTable sorted by point index. The CCD lists its
/// contacts sorted by point index too (rigid_ccd.h), so matching last step's anchors with this step's
/// contacts is one O(n + m) merge: points still in contact keep their anchor, new points get one at their
/// entry position, points that left lose theirs.
///
/// Edge-case policy: a new anchor carries no stretch (no tangential force at entry but damping); F_n <= 0
/// allows no tangential force; k_t = 0 leaves only damping, capped, and the anchor follows the point. A point
/// that leaves contact for one step and comes back starts afresh: contacts that flicker let a held body creep,
/// so the caller should keep resting contacts listed (e.g. with a speculative margin). Not thread-safe per
/// table; distinct tables may be used from distinct threads.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sdfccd/math_types.h"

namespace sdfccd {

/// The tangential law of one contact point (the design takes k_t = k_i and c_t = c_i, after the caps of 2.2).
struct FrictionSettings {
  double friction = 0.5;             ///< Coulomb coefficient mu (dimensionless, >= 0)
  double tangentialStiffness = 0.0;  ///< k_t (N/m, >= 0)
  double tangentialDamping = 0.0;    ///< c_t (N s/m, >= 0)

  /// Throws sdfccd::Error (one line naming the field) on a negative or non-finite value.
  void validate() const;
};

/// Whether a point holds (elastic, below the Coulomb cap) or slides (at the cap).
enum class FrictionState : std::uint8_t {
  Stick,  ///< |F_t| <= mu F_n: the anchor holds
  Slip,   ///< the force was capped at mu F_n (or the anchor was dragged)
};

/// The tangential force at one sample.
struct TangentialForce {
  Vec3 force = Vec3::Zero();    ///< N, on the shell point (minus it on the field body), perpendicular to the normal
  Vec3 stretch = Vec3::Zero();  ///< m, tangential offset s of the point from its anchor
  FrictionState state = FrictionState::Stick;  ///< Slip when the force was capped
};

namespace detail {

/// v - n (n . v), the part of v perpendicular to the unit normal n, component by component (the operations of the
/// Eigen expression, which the compiler left out of line, a call per use in the penalty sampling loop).
inline Vec3 tangentialPart(const Vec3& v, const Vec3& normal) {
  const double along = normal.dot(v);
  return Vec3(v.x() - normal.x() * along, v.y() - normal.y() * along, v.z() - normal.z() * along);
}

}  // namespace detail

/// F_t = -k_t s - c_t v_t, capped at mu max(F_n, 0): s = (p - a) - n (n . (p - a)), v_t likewise from v.
/// All vectors in one frame (world in the penalty sampling loop): pointInWorld and anchorInWorld (m), unit
/// normalInWorld, relativeVelocityInWorld of the shell point with respect to the field body at the point (m/s);
/// normalForce F_n (N). Settings are not validated here (hot loop): validate them once per pair. Inline: the
/// penalty model calls it at every sample.
inline TangentialForce tangentialForce(const Vec3& pointInWorld, const Vec3& anchorInWorld, const Vec3& normalInWorld,
                                       const Vec3& relativeVelocityInWorld, double normalForce,
                                       const FrictionSettings& settings) {
  TangentialForce out;
  out.stretch = detail::tangentialPart(pointInWorld - anchorInWorld, normalInWorld);
  const Vec3 slip = detail::tangentialPart(relativeVelocityInWorld, normalInWorld);
  const double stiffness = -settings.tangentialStiffness;
  const double damping = settings.tangentialDamping;
  out.force = Vec3(stiffness * out.stretch.x() - damping * slip.x(), stiffness * out.stretch.y() - damping * slip.y(),
                   stiffness * out.stretch.z() - damping * slip.z());
  const double cap = settings.friction * std::max(normalForce, 0.0);
  const double magnitude = out.force.norm();
  if (magnitude > cap) {
    const double scale = cap / magnitude;
    out.force = Vec3(out.force.x() * scale, out.force.y() * scale, out.force.z() * scale);
    out.state = FrictionState::Slip;
  }
  return out;
}

/// Where an anchor moves to at the end of a step.
struct AnchorSlip {
  Vec3 anchorInField = Vec3::Zero();           ///< m, field frame
  FrictionState state = FrictionState::Stick;  ///< Slip when it moved
};

/// End-of-step plastic update: if k_t |s| > mu max(F_n, 0), the anchor moves along s until k_t |s| = mu F_n
/// (a += (1 - mu F_n / (k_t |s|)) s: its tangential position becomes p - (mu F_n / k_t) s/|s|, the design's
/// rule, and its offset along the normal is kept); else it stays, bit for bit. Field frame: pointInField (m),
/// anchorInField (m), unit normalInField; normalForce F_n (N) at the end pose.
inline AnchorSlip slipAnchor(const Vec3& pointInField, const Vec3& anchorInField, const Vec3& normalInField,
                             double normalForce, const FrictionSettings& settings) {
  AnchorSlip out;
  out.anchorInField = anchorInField;
  const Vec3 stretch = detail::tangentialPart(pointInField - anchorInField, normalInField);
  const double length = stretch.norm();
  const double elastic = settings.tangentialStiffness * length;
  const double cap = settings.friction * std::max(normalForce, 0.0);
  if (!(elastic > cap) && settings.tangentialStiffness > 0.0) return out;
  if (!(length > 0.0)) return out;  // no stretch: nothing to drag (also k_t = 0 with the point on its anchor)
  // k_t = 0: the stretch carries no force, so the anchor follows the point (it holds nothing).
  const double keep = settings.tangentialStiffness > 0.0 ? cap / elastic : 0.0;
  const double drag = 1.0 - keep;
  out.anchorInField = Vec3(anchorInField.x() + drag * stretch.x(), anchorInField.y() + drag * stretch.y(),
                           anchorInField.z() + drag * stretch.z());
  out.state = FrictionState::Slip;
  return out;
}

/// The anchor of one shell point.
struct FrictionAnchor {
  int point = -1;                     ///< shell point index (>= 0)
  Vec3 anchorInField = Vec3::Zero();  ///< m, field frame
};

/// One of this step's contacts, as the table needs it.
struct AnchorContact {
  int point = -1;                    ///< shell point index; a step's contacts strictly increase in it
  Vec3 entryInField = Vec3::Zero();  ///< m, field frame: p_sdf(t_hit), or p_sdf(0) if it starts inside
};

/// What a match did.
struct AnchorMatchResult {
  int kept = 0;     ///< points still in contact, anchor kept
  int created = 0;  ///< new points, anchored at their entry
  int dropped = 0;  ///< points no longer in contact, anchor forgotten
};

/// The anchors of one pair and role, sorted by point index (lives in the pair's state, dies with it).
///
/// Use per step: match(contacts) (or beginMatch(), matchNext() per contact in increasing point order,
/// endMatch()); then anchors()[i] is contact i's anchor: sample with tangentialForce(), and at the end of the
/// step call updateAnchor(i, ...) for each contact.
class FrictionAnchorTable {
 public:
  /// Matches this step's contacts (strictly increasing point indices, else sdfccd::Error): O(n + m).
  AnchorMatchResult match(const std::vector<AnchorContact>& contacts);

  /// Starts a streaming match (no allocation once the buffers have grown).
  void beginMatch();
  /// The next contact of the step: returns its index in anchors(). Keeps the point's anchor, or anchors it at
  /// entryInField if it has none. Throws sdfccd::Error if point is negative or not above the previous one.
  std::size_t matchNext(int point, const Vec3& entryInField);
  /// Ends the match: anchors of points not matched are dropped. Returns the counts.
  AnchorMatchResult endMatch();

  /// End-of-step update of anchors()[index] (see slipAnchor()); returns Slip if it moved. Throws sdfccd::Error on
  /// an index out of range. Inline: the penalty model calls it for every contact.
  FrictionState updateAnchor(std::size_t index, const Vec3& pointInField, const Vec3& normalInField, double normalForce,
                             const FrictionSettings& settings) {
    if (index >= m_anchors.size()) throwIndexOutOfRange();
    FrictionAnchor& anchor = m_anchors[index];
    const AnchorSlip slip = slipAnchor(pointInField, anchor.anchorInField, normalInField, normalForce, settings);
    anchor.anchorInField = slip.anchorInField;
    return slip.state;
  }

  /// The anchors, sorted by point index; after a match, aligned with the step's contacts.
  const std::vector<FrictionAnchor>& anchors() const { return m_anchors; }
  /// The anchor of `point`, or null (binary search).
  const FrictionAnchor* find(int point) const;
  /// Number of anchors.
  std::size_t size() const { return m_anchors.size(); }
  /// Forgets every anchor.
  void clear();

 private:
  [[noreturn]] static void throwIndexOutOfRange();

  std::vector<FrictionAnchor> m_anchors;   // current, sorted by point
  std::vector<FrictionAnchor> m_previous;  // during a match: last step's anchors
  std::size_t m_cursor = 0;                // during a match: next unvisited entry of m_previous
  AnchorMatchResult m_counts;              // during a match
  bool m_matching = false;
};

}  // namespace sdfccd
