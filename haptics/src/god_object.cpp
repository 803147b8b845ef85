/// @file
/// @brief GodObject: one cycle of constraint-based haptic rendering with CCD (Section 4.2; see god_object.h),
/// instantiated for every field type of field_interface.h.
#include "sdfccd/haptics/god_object.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/tolerances.h"

namespace sdfccd::haptics {

namespace {
/// `v` rounded down to a float.
float roundedDown(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

// Normals within this angle (rad) form one contact patch for the friction solve (reduceContactPatches): a flat
// face of a grid field has gradients equal to about this; the error it admits is of that relative size.
constexpr double kPatchAngle = 1e-6;
}  // namespace

template <class Field>
GodObject<Field>::GodObject(const PointTree& tree, const Field& field, const Rigid& worldFromSdf,
                            const Rigid& worldFromGodStart, const GodObjectSettings& settings)
    : m_tree(tree),
      m_field(&field),
      m_worldFromSdf(worldFromSdf),
      m_sdfFromWorld(worldFromSdf.inverse()),
      m_pose(worldFromGodStart),
      m_settings(settings) {
  if (!worldFromSdf.matrix().allFinite()) throw Error("god object: non-finite pose");
  initialize(worldFromGodStart);
  if (settings.clearanceCache) {
    m_bounds = fieldCullingBounds(field);
    if constexpr (std::is_same_v<Field, GridField>) {
      m_local = LocalLipschitzBounds(field.grid());
      if (settings.axisCertificates) {
        m_axisBounds = sharedAxisLipschitzBounds(field);
        m_axisReach = m_axisBounds->reach();
        m_axisRecords.assign(m_skip.size(), AxisRecord{});
      }
    }
  }
}

template <class Field>
GodObject<Field>::GodObject(const PointTree& tree, ObstacleContacts& obstacles, const Rigid& worldFromGodStart,
                            const GodObjectSettings& settings)
    : m_tree(tree),
      m_obstacles(&obstacles),
      m_worldFromSdf(Rigid::Identity()),
      m_sdfFromWorld(Rigid::Identity()),
      m_pose(worldFromGodStart),
      m_settings(settings) {
  m_settings.clearanceCache = false;  // the cache is the own field's (the obstacles' pairs query every point)
  // The friction solve holds the tool still relative to the world; against a moving obstacle it would have to
  // solve relative to the obstacle's surface velocity, which it does not: refused rather than rendered wrong.
  if (settings.qp.friction > 0.0 && obstacles.anyMoving())
    throw Error("god object: friction against a moving obstacle is not supported (constraint.friction must be 0)");
  initialize(worldFromGodStart);
}

template <class Field>
void GodObject<Field>::initialize(const Rigid& worldFromGodStart) {
  const GodObjectSettings& settings = m_settings;
  const PointTree& tree = m_tree;
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
  if (!(settings.qp.friction >= 0.0) || !std::isfinite(settings.qp.friction))
    throw Error("god object: friction must be finite and >= 0");
  if (settings.qp.frictionFaces < 3 || settings.qp.frictionFaces > 64)
    throw Error("god object: frictionFaces must be in [3, 64]");
  if (!worldFromGodStart.matrix().allFinite()) throw Error("god object: non-finite pose");
  m_inContact.assign(static_cast<std::size_t>(tree.pointCount()), 0);
  m_notInContact.assign(static_cast<std::size_t>(tree.pointCount()), 1);
  if (settings.clearanceCache) {
    const std::size_t n = static_cast<std::size_t>(tree.pointCount());
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

template <class Field>
GodObjectStepResult GodObject<Field>::step(const Rigid& worldFromDevice) {
  GodObjectStepResult out;
  if (!worldFromDevice.matrix().allFinite()) {  // a broken device reading: stay put, render nothing
    out.qpState = ContactQpState::Failed;
    out.contactCount = out.nextContactCount = static_cast<int>(m_contacts.size());
    return out;
  }
  pushByObstacles(out);
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
  out.contactCount = static_cast<int>(m_contacts.size());
  solveContacts(mass, request);
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
  for (const GodObjectContact& c : m_contacts)
    if (c.obstacle < 0) m_candidates.push_back(c.point);
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

// Step 3: a_c, frictionless (NNLS on the dual, exactly as without friction) or with Coulomb friction (Lemke).
template <class Field>
void GodObject<Field>::solveContacts(const Mat6& mass, const Vec6& request) {
  if (m_settings.qp.friction > 0.0) {
    m_normals.clear();
    m_handles.clear();
    for (const GodObjectContact& c : m_contacts) {
      m_normals.push_back(c.normalIntoObstacle);
      m_handles.push_back(c.handle);
    }
    // Coplanar contacts (a face resting on a face: hundreds of points) reduce exactly to their hull.
    reduceContactPatches(m_normals, m_handles, kPatchAngle, m_patchNormals, m_patchHandles);
    m_qp.solveFriction(mass, m_patchNormals, m_patchHandles, request, m_settings.qp, m_qpResult);
    return;
  }
  m_rows.resize(static_cast<Eigen::Index>(m_contacts.size()), 6);
  for (std::size_t k = 0; k < m_contacts.size(); ++k)
    m_rows.row(static_cast<Eigen::Index>(k)) = contactRow(m_contacts[k].normalIntoObstacle, m_contacts[k].handle);
  m_qp.solve(mass, m_rows, request, m_settings.qp, m_qpResult);
}

// Step 5: the earliest contact fraction of the move; collects the reported points as candidates.
template <class Field>
double GodObject<Field>::continuousFraction(const Rigid& tentative, GodObjectStepResult& out) {
  if (m_obstacles) return m_obstacles->continuousFraction(m_pose, tentative, m_settings, out);
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
  rigidCcd(m_tree, *m_field, start, end, ccd, m_ccd);
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
    rigidCcd(m_tree, *m_field, start, end, ccd, m_ccd);
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
        sink.sigma = std::min(m_field->distance(p0), m_settings.slideFloor) - m_settings.sinkTolerance;
        m_field->intersectSegment(p0, p1, sink, m_segment);
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
template <class Field>
void GodObject<Field>::markUnreachablePoints(const Rigid& start, const Rigid& end) {
  const double stepTranslation = (end.translation() - start.translation()).norm();
  const double stepRotation = Eigen::AngleAxisd(end.linear() * start.linear().transpose()).angle();
  const double translationBefore = m_travelTranslation;
  const double rotationBefore = m_travelRotation;
  const Vec3 axisBefore = m_travelAxis;
  // Slack against rounding in the accumulated sums.
  m_travelTranslation += stepTranslation * tolerance::kBoundGrowth;
  m_travelRotation += stepRotation * tolerance::kBoundGrowth;
  // Rounded up: the axis certificates compare differences of these sums (whose own rounding kBoundGrowth covers).
  constexpr double up = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
    m_travelAxis[a] = std::nextafter(
        m_travelAxis[a] + std::abs(end.translation()[a] - start.translation()[a]) * tolerance::kBoundGrowth, up);
  m_travelRotation = std::nextafter(m_travelRotation, up);
  const double travelT = m_travelTranslation;
  const double travelR = m_travelRotation;
  const double lipschitz = m_bounds.lipschitz * tolerance::kBoundGrowth;
  const std::size_t n = m_skip.size();
  const bool ignoreContacts = m_settings.ignoreContactPoints;
  const std::vector<Vec3>& positions = m_tree.shell().positions;
  for (std::size_t p = 0; p < n; ++p) {
    const double radius = static_cast<double>(m_pointRadius[p]);
    if (static_cast<double>(m_clearanceBudget[p]) > travelT + travelR * radius) {
      m_skip[p] = 1;
      continue;
    }
    if (m_axisBounds && axisRecordHolds(m_axisRecords[p], radius)) {
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
                             : m_field->distance(pointInSdf);
      // A relative margin against the different rounding of the segment query's own evaluation of phi, on the
      // magnitudes involved: phi and sigma, and the point's coordinates (its position and phi round relative to
      // them; far from the field's origin phi can be small beside them).
      const double clearance =
          phi - m_settings.sigma -
          tolerance::kRelativeSlack * (std::abs(phi) + std::abs(m_settings.sigma) + pointInSdf.norm());
      double allowedTravel = clearance / lipschitz;
      if (!m_local.empty() && m_bounds.box.contains(pointInSdf))
        allowedTravel =
            std::min(clearance / (m_local.lipschitzNear(pointInSdf) * tolerance::kBoundGrowth), m_local.reach());
      const double budget = allowedTravel + translationBefore + rotationBefore * radius;
      float f = static_cast<float>(budget);
      if (static_cast<double>(f) > budget) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
      m_clearanceBudget[p] = f;
      m_skip[p] = static_cast<double>(f) > travelT + travelR * radius;
      if (m_axisBounds) {
        AxisRecord& record = m_axisRecords[p];
        const int block = m_axisBounds->blockOf(pointInSdf);  // -1 outside the box: no axis certificate
        record.clearance = block < 0 ? -1.0f : roundedDown(clearance);
        if (block >= 0) {
          const AxisLipschitzBounds::Block& g = m_axisBounds->block(block);
          record.gx = g.x, record.gy = g.y, record.gz = g.z, record.gNorm = g.norm;
          record.travelX = roundedDown(axisBefore.x());
          record.travelY = roundedDown(axisBefore.y());
          record.travelZ = roundedDown(axisBefore.z());
          record.travelRotation = roundedDown(rotationBefore);
        }
        if (!m_skip[p]) m_skip[p] = axisRecordHolds(record, radius);
      }
    }
  }
  if (ignoreContacts)
    for (const GodObjectContact& c : m_contacts)
      if (c.obstacle < 0) m_skip[static_cast<std::size_t>(c.point)] = 1;
}

// The discrete variant: every point near the surface at the new pose.
template <class Field>
void GodObject<Field>::discreteCandidates(GodObjectStepResult& out) {
  if (m_obstacles) {
    m_obstacles->discreteCandidates(m_pose, m_settings, out);
    return;
  }
  const Rigid at = m_sdfFromWorld * m_pose;
  RigidCcdSettings ccd;
  ccd.sigma = m_settings.sigma + m_settings.contactThreshold;
  ccd.mode = CcdMode::FirstHit;
  ccd.octree = m_settings.octree;
  ccd.threads = m_settings.threads;
  rigidCcd(m_tree, *m_field, at, at, ccd, m_ccd);
  out.segmentQueries += m_ccd.stats.segmentQueries;
  for (const PointContact& c : m_ccd.contacts) m_candidates.push_back(c.point);
}

// Step 6: the contact set at the new pose.
template <class Field>
void GodObject<Field>::updateContacts(GodObjectStepResult& out) {
  if (m_obstacles) {  // every contact is an obstacle's
    m_next.clear();
    out.newContacts = 0;
    m_obstacles->appendContacts(m_pose, m_settings, m_next, out);
    m_contacts.swap(m_next);
    out.minContactDistance = 0.0;
    for (std::size_t k = 0; k < m_contacts.size(); ++k)
      out.minContactDistance =
          k == 0 ? m_contacts[k].distance : std::min(out.minContactDistance, m_contacts[k].distance);
    out.nextContactCount = static_cast<int>(m_contacts.size());
    return;
  }
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
    const double phi = m_field->distance(pointInSdf);
    if (!(phi - m_settings.sigma <= m_settings.contactThreshold)) continue;
    const Vec3 gradient = m_field->gradient(pointInSdf);
    const double len = gradient.norm();
    if (!(len > tolerance::kMinDirectionLength) || !std::isfinite(len))
      continue;  // no direction (medial point): no constraint
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

// Moving obstacles (haptic_obstacles.h): they jump to their pose at the cycle's time and push the god-object out
// of their way before the usual cycle runs against them held there.
template <class Field>
void GodObject<Field>::pushByObstacles(GodObjectStepResult& out) {
  if (!m_obstacles || !m_obstacles->moveTo(m_obstacleTime)) return;
  const Mat6 mass = massMatrix(m_settings.mass, worldInertia(m_pose, m_settings.inertiaDiagonal));
  m_pose = m_obstacles->push(m_pose, mass, m_settings, m_contacts, out);
}

#define SDFCCD_INSTANTIATE_GOD_OBJECT(Field) template class GodObject<Field>;
SDFCCD_FOR_EACH_FIELD(SDFCCD_INSTANTIATE_GOD_OBJECT)
#undef SDFCCD_INSTANTIATE_GOD_OBJECT

}  // namespace sdfccd::haptics
