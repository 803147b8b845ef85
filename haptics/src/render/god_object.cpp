/// @file
/// @brief GodObject: one cycle of constraint-based haptic rendering with CCD (Section 4.2; see god_object.h). The
/// contact queries of steps 5 and 6 are the obstacles' (contact/obstacle_pair.h).
#include "sdfccd/haptics/god_object.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "sdfccd/error.h"

namespace sdfccd::haptics {

namespace {

// Normals within this angle (rad) form one contact patch for the friction solve (reduceContactPatches): a flat
// face of a grid field has gradients equal to about this; the error it admits is of that relative size.
constexpr double kPatchAngle = 1e-6;

/// Throws sdfccd::Error on settings the cycle cannot run with.
void checkSettings(const GodObjectSettings& settings) {
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
}

}  // namespace

GodObject::GodObject(ObstacleContacts contacts, const Rigid& worldFromGodStart, const GodObjectSettings& settings)
    : m_obstacles(std::move(contacts)), m_pose(worldFromGodStart), m_settings(settings) {
  checkSettings(settings);
  if (!worldFromGodStart.matrix().allFinite()) throw Error("god object: non-finite pose");
  // The friction solve holds the tool still relative to the world; against a moving obstacle it would have to
  // solve relative to the obstacle's surface velocity, which it does not: refused rather than rendered wrong.
  if (settings.qp.friction > 0.0 && m_obstacles.anyMoving())
    throw Error("god object: friction against a moving obstacle is not supported (constraint.friction must be 0)");
  m_obstacles.prepare(m_settings);
}

GodObjectStepResult GodObject::step(const Rigid& worldFromDevice) {
  GodObjectStepResult out;
  if (!worldFromDevice.matrix().allFinite()) {  // a broken device reading: stay put, render nothing
    out.qpState = ContactQpState::Failed;
    out.contactCount = out.nextContactCount = static_cast<int>(m_contacts.size());
    return out;
  }
  pushByObstacles(out);
  const double ks = m_settings.couplingGain;
  out.unconstrained = ks * poseDifference(m_pose, worldFromDevice);
  const Vec6 request = out.unconstrained;
  const Vec3 lift = depthCorrection();
  const Mat6 mass = massMatrix(m_settings.mass, worldInertia(m_pose, m_settings.inertiaDiagonal));
  out.contactCount = static_cast<int>(m_contacts.size());
  solveContacts(mass, request);
  out.qpState = m_qpResult.state;
  out.blocked = m_qpResult.blocked;
  out.constrained = m_qpResult.acceleration;
  const double kh = m_settings.renderStiffness / (ks * m_settings.mass);
  out.wrenchOnDevice = kh * (mass * (out.constrained - out.unconstrained));

  const Vec6 move = limitedMove(lift);
  const Rigid tentative = displacePose(m_pose, move);
  if (m_settings.continuous) {
    out.fraction = m_obstacles.continuousFraction(m_pose, tentative, m_settings, out);
    m_pose = out.fraction >= 1.0 ? tentative : displacePose(m_pose, out.fraction * move);
  } else {
    m_pose = tentative;
    m_obstacles.discreteCandidates(m_pose, m_settings, out);
  }
  updateContacts(out);
  return out;
}

// Contacts that drifted below sigma (second-order effects of rotation and curvature, which the linearized
// constraints cannot see) lift the move outwards by the deepest shortfall, added after the QP (so the constraint cone
// is unchanged and the QP stays a projection onto a cone).
Vec3 GodObject::depthCorrection() const {
  if (!(m_settings.depthCorrection > 0.0)) return Vec3::Zero();
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
  return len > 0.0 ? Vec3((m_settings.depthCorrection * deepest / len) * outwards) : Vec3::Zero();
}

// Step 3: a_c, frictionless (NNLS on the dual, exactly as without friction) or with Coulomb friction (Lemke).
void GodObject::solveContacts(const Mat6& mass, const Vec6& request) {
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

// Step 4: the tentative move, limited per cycle (a positive scaling keeps J a <= 0).
Vec6 GodObject::limitedMove(const Vec3& lift) const {
  Vec6 move = m_qpResult.acceleration;
  move.head<3>() += lift;
  double scale = 1.0;
  const double lin = move.head<3>().norm();
  const double ang = move.tail<3>().norm();
  if (m_settings.maxStepTranslation > 0.0 && lin > m_settings.maxStepTranslation)
    scale = std::min(scale, m_settings.maxStepTranslation / lin);
  if (m_settings.maxStepRotation > 0.0 && ang > m_settings.maxStepRotation)
    scale = std::min(scale, m_settings.maxStepRotation / ang);
  move *= scale;
  return move;
}

// Step 6: the contact set at the new pose, every obstacle's.
void GodObject::updateContacts(GodObjectStepResult& out) {
  m_next.clear();
  out.newContacts = 0;
  m_obstacles.appendContacts(m_pose, m_settings, m_next, out);
  m_contacts.swap(m_next);
  out.minContactDistance = 0.0;
  for (std::size_t k = 0; k < m_contacts.size(); ++k)
    out.minContactDistance = k == 0 ? m_contacts[k].distance : std::min(out.minContactDistance, m_contacts[k].distance);
  out.nextContactCount = static_cast<int>(m_contacts.size());
}

// Moving obstacles (haptic_obstacles.h): they jump to their pose at the cycle's time and push the god-object out
// of their way before the usual cycle runs against them held there.
void GodObject::pushByObstacles(GodObjectStepResult& out) {
  if (!m_obstacles.moveTo(m_obstacleTime)) return;
  const Mat6 mass = massMatrix(m_settings.mass, worldInertia(m_pose, m_settings.inertiaDiagonal));
  m_pose = m_obstacles.push(m_pose, mass, m_settings, m_contacts, out);
}

}  // namespace sdfccd::haptics
