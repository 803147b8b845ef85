/// @file
/// @brief GodObject: constraint-based 6-DoF haptic rendering with continuous collision detection
/// (paper Section 4.2, after Ortega et al. [10]).
///
/// @details A quasi-static "god object" (zero velocity at all times) carries the manipulated point shell and
/// stays on the surface of the static object (a distance field). One simulation cycle, given the device pose
/// x_h and the god-object pose x_s:
///   1. a_u = k_s (x_h - x_s)                                    (eq. 6; 6-D pose difference, world axes)
///   2. one row J_k = [n_k^T, (r_k x n_k)^T] per contact k        (eq. 7; n_k = -grad(phi)/|grad(phi)|, the
///      static object's normal pointing into it; r_k from the god-object's centre to the point)
///   3. a_c = argmin ||a - a_u||_M subject to J a <= 0            (contact_qp.h)
///   4. the tentative pose: one symplectic Euler step from rest with a unit cycle time, i.e. the
///      displacement a_c (quasi-static: k_s is the fraction of the gap closed per cycle), optionally scaled
///      down so that one cycle moves at most maxStepTranslation / maxStepRotation (scaling keeps J a <= 0)
///   5. continuous collision detection of the shell from x_s to the tentative pose (FirstHit leaves), with
///      the points in contact in the last cycle ignored (the paper's sliding remedy); the god-object moves
///      only to the earliest contact fraction t_c
///   6. the contact set for the next cycle: the points the CCD reported plus the previously ignored points,
///      checked discretely at the new pose: phi - sigma <= contactThreshold keeps them
///   7. F_c = k_h M (a_c - a_u), rendered to the device.
///
/// The constraints are linear in the motion, but a rotating body's points follow chords that sink by
/// ~ r theta^2 / 2 per cycle at active contacts (and so does sliding over concave curvature). Two additions
/// keep that from accumulating: maxStepRotation bounds theta per cycle, and depthCorrection adds an outward
/// lift to the constrained move for contacts that drifted below sigma (after the QP: the cone of the QP is
/// unchanged, and a user pressing into the contact cannot cancel the lift, as a bias of a_u would be
/// projected away; without it, a point held at slideFloor freezes every move that sinks it to second order,
/// e.g. sliding along the inside of a bent tube).
///
/// Two details beyond the paper, both switchable:
/// - sigma > 0 (a small fraction of a voxel) keeps the god-object a hair off the surface, so the discrete
///   re-check of step 6 sees the contacts it just made and rounding never puts a point below phi = 0.
/// - guardIgnoredPoints: the ignored points get their own CCD at the lower level set slideFloor (<= sigma),
///   so a sliding point that runs into a concave corner (where the QP's first-order constraint does not see
///   the other wall), or sinks through the second-order effects of curvature and rotation, is stopped there
///   instead of being re-checked only after it went through. A point already under the floor (by rounding)
///   is held at its own depth (less sinkTolerance): without that, it would be free to sink once under.
///
/// The discrete variant (continuous = false; paper Fig. 11) skips step 5: it moves to the tentative pose
/// and takes as contacts every point with phi - sigma <= contactThreshold there.
///
/// Clearance cache (clearanceCache, on by default; the results are bit-identical with it off): step 5 skips
/// every point that provably cannot reach sigma during the move. Per point it keeps the clearance
/// phi - sigma where it was last evaluated and the body's travel since then, bounded by the sum over cycles
/// of |translation of the centre| + |rotation angle| * |point - centre| (a bound on every point's chord). With
/// the field's gradient bound L (field_culling_bounds.h), phi anywhere on the point's later segments stays
/// above clearance - L * travel (the path from the evaluation point to any later position runs inside the
/// field's box, which is convex, where L holds; outside the box the segment query sees no contact). Grid
/// fields use the bound of the point's neighbourhood instead (local_lipschitz_bounds.h: about 1 near a smooth
/// wall where the global bound is sqrt(3)), valid for a travel up to its reach, after which the point is
/// re-evaluated. Points whose bound runs out are re-evaluated at the start of the move (one trilinear lookup) and
/// queried by CCD only if the move itself can use up their clearance. The cycle then costs O(points) cheap tests, and
/// segment queries only for the points near the surface that move towards it; without it, a body resting in
/// a tight fit (the peg fully inserted: every side point within 0.07 voxel of the wall) re-queries every point
/// near the wall every cycle although the god-object barely moves.
///
/// Frames: the shell frame is the god-object's body frame and its origin is the centre of mass.
/// Thread safety: one GodObject per simulation thread; the tree and the field are only read.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "sdfccd/error.h"
#include "sdfccd/haptics/contact_qp.h"
#include "sdfccd/haptics/local_lipschitz_bounds.h"
#include "sdfccd/haptics/rigid_body_state.h"
#include "sdfccd/haptics/spatial_types.h"
#include "sdfccd/math_types.h"
#include "sdfccd/shell/point_tree.h"
#include "sdfccd/ccd/rigid_ccd.h"

namespace sdfccd::haptics {

/// Settings of the constraint-based renderer.
struct GodObjectSettings {
  double couplingGain = 0.5;                    ///< k_s of eq. (6) (per cycle; the paper uses 0.5)
  double renderStiffness = 300.0;               ///< N/m: k_h M (a_c - a_u) with k_h = renderStiffness / (k_s mass)
  double mass = 0.1;                            ///< kg, the god-object's mass (the QP's metric)
  Vec3 inertiaDiagonal = Vec3::Constant(1e-4);  ///< kg m^2, body axes
  double sigma = 0.0;                           ///< contact level set (model units), >= 0
  double contactThreshold = 0.0;                ///< model units: a point with phi - sigma <= this is in contact
  double slideFloor = 0.0;                      ///< level set of the ignored points' guard CCD (model units, <= sigma)
  double sinkTolerance = 0.0;                   ///< model units: how much deeper an ignored point already under the
                                                ///< floor may go in one cycle (0: not at all)
  bool ignoreContactPoints = true;              ///< the paper's sliding remedy (off only to show why it is needed)
  bool guardIgnoredPoints = true;               ///< run the guard CCD on the ignored points
  double maxStepTranslation = 0.0;              ///< model units per cycle (0: unlimited)
  double maxStepRotation = 0.01;                ///< rad per cycle (0: unlimited); keeps point paths near-linear
  double depthCorrection = 1.0;                 ///< gain of the outward bias for contacts below sigma (0: off)
  bool continuous = true;                       ///< false: the discrete-collision variant (Fig. 11)
  bool clearanceCache = true;                   ///< skip points that provably cannot reach sigma (see @details)
  OctreeMode octree = OctreeMode::Leaves;       ///< cell skipping at haptic rates (Section 4.1: leaves)
  CcdMethod ccdMethod = CcdMethod::Exact;
  int threads = 1;  ///< CCD worker threads
  ContactQpSettings qp;
};

/// One contact of the god-object.
struct GodObjectContact {
  int point = -1;                          ///< shell point index
  Vec3 normalIntoObstacle = Vec3::Zero();  ///< n_k, world, unit
  Vec3 handle = Vec3::Zero();              ///< r_k, world (from the centre to the point)
  double distance = 0.0;                   ///< phi at the point (model units)
};

/// What one simulation cycle did.
struct GodObjectStepResult {
  ContactQpState qpState = ContactQpState::Solved;
  bool blocked = false;                ///< the QP's optimum was ~0 although a_u was not
  Vec6 unconstrained = Vec6::Zero();   ///< a_u
  Vec6 constrained = Vec6::Zero();     ///< a_c
  Vec6 wrenchOnDevice = Vec6::Zero();  ///< F_c (N, N m)
  double fraction = 1.0;               ///< how much of the tentative move was made (t_c)
  int contactCount = 0;                ///< contacts used by the QP this cycle
  int nextContactCount = 0;            ///< contacts after the move (used next cycle)
  int newContacts = 0;                 ///< of those, points that were not in contact before
  double minContactDistance = 0.0;     ///< smallest phi over the next contact set (model units)
  std::int64_t segmentQueries = 0;     ///< CCD work
};

template <class Field>
class GodObject {
 public:
  /// `worldFromSdf` places the static field. Throws sdfccd::Error on bad settings.
  GodObject(const PointTree& tree, const Field& field, const Rigid& worldFromSdf, const Rigid& worldFromGodStart,
            const GodObjectSettings& settings)
      : m_tree(tree),
        m_field(field),
        m_worldFromSdf(worldFromSdf),
        m_sdfFromWorld(worldFromSdf.inverse()),
        m_pose(worldFromGodStart),
        m_settings(settings) {
    const auto finitePositive = [](double v) { return std::isfinite(v) && v > 0.0; };
    if (!finitePositive(settings.couplingGain) || settings.couplingGain > 1.0)
      throw Error("god object: couplingGain must be in (0, 1]");
    if (!finitePositive(settings.mass) || !finitePositive(settings.inertiaDiagonal.minCoeff()) ||
        !settings.inertiaDiagonal.allFinite())
      throw Error("god object: mass and inertia must be positive and finite");
    if (!(settings.renderStiffness >= 0.0) || !std::isfinite(settings.renderStiffness))
      throw Error("god object: renderStiffness must be finite and >= 0");
    if (!(settings.sinkTolerance >= 0.0) || !std::isfinite(settings.sinkTolerance))
      throw Error("god object: sinkTolerance must be finite and >= 0");
    if (!(settings.sigma >= 0.0) || !(settings.contactThreshold >= 0.0) || !std::isfinite(settings.sigma) ||
        !std::isfinite(settings.contactThreshold) || !std::isfinite(settings.slideFloor) ||
        settings.slideFloor > settings.sigma)
      throw Error("god object: need 0 <= sigma, 0 <= contactThreshold, slideFloor <= sigma (finite)");
    if (!(settings.maxStepTranslation >= 0.0) || !(settings.maxStepRotation >= 0.0))
      throw Error("god object: step limits must be >= 0");
    if (!worldFromGodStart.matrix().allFinite() || !worldFromSdf.matrix().allFinite())
      throw Error("god object: non-finite pose");
    m_inContact.assign(static_cast<std::size_t>(tree.pointCount()), 0);
    m_notInContact.assign(static_cast<std::size_t>(tree.pointCount()), 1);
    if (settings.clearanceCache) {
      const std::size_t n = static_cast<std::size_t>(tree.pointCount());
      m_bounds = fieldCullingBounds(field);
      if constexpr (std::is_same_v<Field, GridField>) m_local = LocalLipschitzBounds(field.grid());
      m_skip.assign(n, 0);
      m_clearanceBudget.assign(n, -std::numeric_limits<float>::infinity());  // unknown: evaluate first
      m_pointRadius.resize(n);
      for (std::size_t p = 0; p < n; ++p) {
        // Rounded up to float: a bound of |point - centre| (the shell frame's origin is the centre).
        const double r = tree.shell().positions[p].norm();
        float f = static_cast<float>(r);
        if (static_cast<double>(f) < r) f = std::nextafter(f, std::numeric_limits<float>::infinity());
        m_pointRadius[p] = f;
      }
    }
  }

  /// One simulation cycle towards the device pose.
  GodObjectStepResult step(const Rigid& worldFromDevice) {
    GodObjectStepResult out;
    if (!worldFromDevice.matrix().allFinite()) {  // a broken device reading: stay put, render nothing
      out.qpState = ContactQpState::Failed;
      out.contactCount = out.nextContactCount = static_cast<int>(m_contacts.size());
      return out;
    }
    const double ks = m_settings.couplingGain;
    out.unconstrained = ks * poseDifference(m_pose, worldFromDevice);
    // Depth correction: contacts that drifted below sigma (second-order effects of rotation and curvature,
    // which the linearized constraints cannot see) lift the move outwards by the deepest shortfall, added
    // after the QP (so the constraint cone is unchanged and the QP stays a projection onto a cone).
    const Vec6 request = out.unconstrained;
    Vec3 lift = Vec3::Zero();
    if (m_settings.depthCorrection > 0.0) {
      Vec3 outwards = Vec3::Zero();
      double deepest = 0.0;
      for (const GodObjectContact& c : m_contacts) {
        const double shortfall = m_settings.sigma - c.distance;
        if (shortfall > 0.0) {
          outwards -= shortfall * c.normalIntoObstacle;
          deepest = std::max(deepest, shortfall);
        }
      }
      const double len = outwards.norm();
      if (len > 0.0) lift = (m_settings.depthCorrection * deepest / len) * outwards;
    }
    const Mat6 mass = massMatrix(m_settings.mass, worldInertia(m_pose, m_settings.inertiaDiagonal));
    m_rows.resize(static_cast<Eigen::Index>(m_contacts.size()), 6);
    for (std::size_t k = 0; k < m_contacts.size(); ++k)
      m_rows.row(static_cast<Eigen::Index>(k)) = contactRow(m_contacts[k].normalIntoObstacle, m_contacts[k].handle);
    out.contactCount = static_cast<int>(m_contacts.size());
    m_qp.solve(mass, m_rows, request, m_settings.qp, m_qpResult);
    out.qpState = m_qpResult.state;
    out.blocked = m_qpResult.blocked;
    out.constrained = m_qpResult.acceleration;
    const double kh = m_settings.renderStiffness / (ks * m_settings.mass);
    out.wrenchOnDevice = kh * (mass * (out.constrained - out.unconstrained));

    // The tentative move, limited per cycle (a positive scaling keeps J a <= 0).
    Vec6 move = out.constrained;
    move.head<3>() += lift;
    double scale = 1.0;
    const double lin = move.head<3>().norm();
    const double ang = move.tail<3>().norm();
    if (m_settings.maxStepTranslation > 0.0 && lin > m_settings.maxStepTranslation)
      scale = std::min(scale, m_settings.maxStepTranslation / lin);
    if (m_settings.maxStepRotation > 0.0 && ang > m_settings.maxStepRotation)
      scale = std::min(scale, m_settings.maxStepRotation / ang);
    move *= scale;
    const Rigid tentative = displacePose(m_pose, move);

    m_candidates.clear();
    for (const GodObjectContact& c : m_contacts) m_candidates.push_back(c.point);
    if (m_settings.continuous) {
      out.fraction = continuousFraction(tentative, out);
      m_pose = out.fraction >= 1.0 ? tentative : displacePose(m_pose, out.fraction * move);
    } else {
      m_pose = tentative;
      discreteCandidates(out);
    }
    updateContacts(out);
    return out;
  }

  const Rigid& pose() const { return m_pose; }  ///< worldFromGod
  const std::vector<GodObjectContact>& contacts() const { return m_contacts; }
  const GodObjectSettings& settings() const { return m_settings; }
  Rigid sdfFromGod() const { return m_sdfFromWorld * m_pose; }

 private:
  // Step 5: the earliest contact fraction of the move; collects the reported points as candidates.
  double continuousFraction(const Rigid& tentative, GodObjectStepResult& out) {
    const Rigid start = m_sdfFromWorld * m_pose;
    const Rigid end = m_sdfFromWorld * tentative;
    RigidCcdSettings ccd;
    ccd.sigma = m_settings.sigma;
    ccd.mode = CcdMode::FirstHit;
    ccd.method = m_settings.ccdMethod;
    ccd.octree = m_settings.octree;
    ccd.threads = m_settings.threads;
    ccd.ignoredPoints = m_settings.ignoreContactPoints ? &m_inContact : nullptr;
    if (m_settings.clearanceCache) {
      markUnreachablePoints(start, end);
      ccd.ignoredPoints = &m_skip;
      ccd.useTree = false;  // the few points left are visited one by one (the same leaf query as the tree's)
    }
    rigidCcd(m_tree, m_field, start, end, ccd, m_ccd);
    out.segmentQueries += m_ccd.stats.segmentQueries;
    double fraction = 1.0;
    for (const PointContact& c : m_ccd.contacts) {
      fraction = std::min(fraction, c.fraction);
      m_candidates.push_back(c.point);
    }
    if (m_settings.ignoreContactPoints && m_settings.guardIgnoredPoints && !m_contacts.empty()) {
      // The ignored points may slide but not sink below slideFloor. Points already below it (rounding,
      // curvature) start inside and must not freeze the god-object: only proper hits count.
      ccd.sigma = m_settings.slideFloor;
      ccd.ignoredPoints = &m_notInContact;
      // Few contacts: visiting them point by point beats re-testing every inner node of the tree.
      ccd.useTree = m_contacts.size() * 16 > static_cast<std::size_t>(m_tree.pointCount());
      rigidCcd(m_tree, m_field, start, end, ccd, m_ccd);
      out.segmentQueries += m_ccd.stats.segmentQueries;
      SegmentCcdSettings sink;
      sink.mode = CcdMode::FirstHit;
      sink.method = m_settings.ccdMethod;
      sink.octree = m_settings.octree;
      for (const PointContact& c : m_ccd.contacts) {
        if (c.state == SegmentState::Hit) {
          fraction = std::min(fraction, c.fraction);
        } else if (c.state == SegmentState::StartsInside) {
          // Already below the floor (rounding, the chord of a rotation): it may slide but not sink deeper than
          // where it is, less sinkTolerance; otherwise it would be free to go down once under the floor.
          const Vec3& x = m_tree.shell().positions[static_cast<std::size_t>(c.point)];
          const Vec3 p0 = start * x;
          const Vec3 p1 = end * x;
          sink.sigma = std::min(m_field.distance(p0), m_settings.slideFloor) - m_settings.sinkTolerance;
          m_field.intersectSegment(p0, p1, sink, m_segment);
          ++out.segmentQueries;
          if (m_segment.state == SegmentState::Hit) fraction = std::min(fraction, m_segment.fraction);
        }
      }
    }
    return std::clamp(fraction, 0.0, 1.0);
  }

  // The clearance cache (see @details): m_skip[p] = 1 for the points ignored by the rule of the last contacts and
  // for those that cannot reach sigma on the move start -> end. Per point, m_clearanceBudget holds
  // (phi - sigma) / L + travelTranslation + travelRotation * radius at its last evaluation (rounded down to float),
  // so the point is safe while budget > travelTranslation + travelRotation * radius now, travel included.
  void markUnreachablePoints(const Rigid& start, const Rigid& end) {
    const double stepTranslation = (end.translation() - start.translation()).norm();
    const double stepRotation = Eigen::AngleAxisd(end.linear() * start.linear().transpose()).angle();
    const double translationBefore = m_travelTranslation;
    const double rotationBefore = m_travelRotation;
    // Slack against rounding in the accumulated sums.
    m_travelTranslation += stepTranslation * (1.0 + 1e-9);
    m_travelRotation += stepRotation * (1.0 + 1e-9);
    const double travelT = m_travelTranslation;
    const double travelR = m_travelRotation;
    const double lipschitz = m_bounds.lipschitz * (1.0 + 1e-9);
    const std::size_t n = m_skip.size();
    const bool ignoreContacts = m_settings.ignoreContactPoints;
    const std::vector<Vec3>& positions = m_tree.shell().positions;
    for (std::size_t p = 0; p < n; ++p) {
      const double radius = static_cast<double>(m_pointRadius[p]);
      if (static_cast<double>(m_clearanceBudget[p]) > travelT + travelR * radius) {
        m_skip[p] = 1;
        continue;
      }
      m_skip[p] = 0;
      // Out of budget: evaluate phi where the point starts this move.
      const Vec3 pointInSdf = start * positions[p];
      {
        // Inside the box: phi there. Outside (the segment query sees no contact there): a path into the box
        // crosses a face (phi >= boundaryMin) after at least the distance to the box, so L * that distance +
        // boundaryMin plays the part of phi.
        const double phi = m_bounds.bounded && !m_bounds.box.contains(pointInSdf)
                               ? m_bounds.lipschitz * m_bounds.box.exteriorDistance(pointInSdf) + m_bounds.boundaryMin
                               : m_field.distance(pointInSdf);
        // A relative margin against the different rounding of the segment query's own evaluation of phi.
        const double clearance = phi - m_settings.sigma - 1e-9 * (std::abs(phi) + std::abs(m_settings.sigma));
        double allowedTravel = clearance / lipschitz;
        if (!m_local.empty() && m_bounds.box.contains(pointInSdf))
          allowedTravel = std::min(clearance / (m_local.lipschitzNear(pointInSdf) * (1.0 + 1e-9)), m_local.reach());
        const double budget = allowedTravel + translationBefore + rotationBefore * radius;
        float f = static_cast<float>(budget);
        if (static_cast<double>(f) > budget) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
        m_clearanceBudget[p] = f;
        m_skip[p] = static_cast<double>(f) > travelT + travelR * radius;
      }
    }
    if (ignoreContacts)
      for (const GodObjectContact& c : m_contacts) m_skip[static_cast<std::size_t>(c.point)] = 1;
  }

  // The discrete variant: every point near the surface at the new pose.
  void discreteCandidates(GodObjectStepResult& out) {
    const Rigid at = m_sdfFromWorld * m_pose;
    RigidCcdSettings ccd;
    ccd.sigma = m_settings.sigma + m_settings.contactThreshold;
    ccd.mode = CcdMode::FirstHit;
    ccd.octree = m_settings.octree;
    ccd.threads = m_settings.threads;
    rigidCcd(m_tree, m_field, at, at, ccd, m_ccd);
    out.segmentQueries += m_ccd.stats.segmentQueries;
    for (const PointContact& c : m_ccd.contacts) m_candidates.push_back(c.point);
  }

  // Step 6: the contact set at the new pose.
  void updateContacts(GodObjectStepResult& out) {
    std::sort(m_candidates.begin(), m_candidates.end());
    m_candidates.erase(std::unique(m_candidates.begin(), m_candidates.end()), m_candidates.end());
    const Rigid sdfFromGod = m_sdfFromWorld * m_pose;
    const Mat3 worldFromSdfRotation = m_worldFromSdf.linear();
    m_next.clear();
    out.newContacts = 0;
    out.minContactDistance = 0.0;
    bool first = true;
    for (const int p : m_candidates) {
      const Vec3& pointInShell = m_tree.shell().positions[static_cast<std::size_t>(p)];
      const Vec3 pointInSdf = sdfFromGod * pointInShell;
      const double phi = m_field.distance(pointInSdf);
      if (!(phi - m_settings.sigma <= m_settings.contactThreshold)) continue;
      const Vec3 gradient = m_field.gradient(pointInSdf);
      const double len = gradient.norm();
      if (!(len > 1e-12) || !std::isfinite(len)) continue;  // no direction (medial point): no constraint
      GodObjectContact c;
      c.point = p;
      c.normalIntoObstacle = -(worldFromSdfRotation * gradient) / len;
      c.handle = m_pose.linear() * pointInShell;
      c.distance = phi;
      if (!m_inContact[static_cast<std::size_t>(p)]) ++out.newContacts;
      out.minContactDistance = first ? phi : std::min(out.minContactDistance, phi);
      first = false;
      m_next.push_back(c);
    }
    for (const GodObjectContact& c : m_contacts) {
      m_inContact[static_cast<std::size_t>(c.point)] = 0;
      m_notInContact[static_cast<std::size_t>(c.point)] = 1;
    }
    m_contacts.swap(m_next);
    for (const GodObjectContact& c : m_contacts) {
      m_inContact[static_cast<std::size_t>(c.point)] = 1;
      m_notInContact[static_cast<std::size_t>(c.point)] = 0;
    }
    out.nextContactCount = static_cast<int>(m_contacts.size());
  }

  const PointTree& m_tree;
  const Field& m_field;
  Rigid m_worldFromSdf;
  Rigid m_sdfFromWorld;
  Rigid m_pose;
  GodObjectSettings m_settings;
  std::vector<GodObjectContact> m_contacts;
  std::vector<GodObjectContact> m_next;
  std::vector<int> m_candidates;
  std::vector<std::uint8_t> m_inContact;
  std::vector<std::uint8_t> m_notInContact;
  ConstraintRows m_rows;
  ContactQpSolver m_qp;
  ContactQpResult m_qpResult;
  RigidCcdResult m_ccd;
  SegmentCcdResult m_segment;
  // The clearance cache (clearanceCache).
  FieldCullingBounds m_bounds;
  LocalLipschitzBounds m_local;  // grid fields only
  std::vector<std::uint8_t> m_skip;
  std::vector<float> m_clearanceBudget;  // model units (see markUnreachablePoints)
  std::vector<float> m_pointRadius;      // |point - centre|, rounded up
  double m_travelTranslation = 0.0;      // sum of |centre translation| over the moves (model units)
  double m_travelRotation = 0.0;         // sum of rotation angles over the moves (rad)
};

}  // namespace sdfccd::haptics
