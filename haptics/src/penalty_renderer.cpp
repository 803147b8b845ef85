/// @file
/// @brief PenaltyRenderer: one haptic tick of penalty rendering (Section 4.1; see penalty_renderer.h),
/// instantiated for every field type of field_interface.h.
#include "sdfccd/haptics/penalty_renderer.h"

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <type_traits>

#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/tolerances.h"

namespace sdfccd::haptics {

template <class Field>
PenaltyRenderer<Field>::PenaltyRenderer(const PointTree& tree, const Field& field, const Rigid& worldFromSdf,
                                        const Rigid& worldFromBodyStart, const PenaltyRendererSettings& settings)
    : PenaltyRenderer(tree, &field, nullptr, worldFromSdf, worldFromBodyStart, settings) {}

template <class Field>
PenaltyRenderer<Field>::PenaltyRenderer(const PointTree& tree, ObstacleContacts& obstacles,
                                        const Rigid& worldFromBodyStart, const PenaltyRendererSettings& settings)
    : PenaltyRenderer(tree, nullptr, &obstacles, Rigid::Identity(), worldFromBodyStart, settings) {}

template <class Field>
PenaltyRenderer<Field>::PenaltyRenderer(const PointTree& tree, const Field* field, ObstacleContacts* obstacles,
                                        const Rigid& worldFromSdf, const Rigid& worldFromBodyStart,
                                        const PenaltyRendererSettings& settings)
    : m_tree(tree),
      m_field(field),
      m_obstacles(obstacles),
      m_worldFromSdf(worldFromSdf),
      m_sdfFromWorld(worldFromSdf.inverse()),
      m_settings(settings) {
  const auto finitePositive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!finitePositive(settings.mass) || !finitePositive(settings.inertiaDiagonal.minCoeff()) ||
      !settings.inertiaDiagonal.allFinite() || !finitePositive(settings.timestep))
    throw Error("penalty renderer: mass, inertia and timestep must be positive and finite");
  if (!worldFromBodyStart.matrix().allFinite() || !worldFromSdf.matrix().allFinite())
    throw Error("penalty renderer: non-finite pose");
  if (settings.couplingIntegration != CouplingIntegration::Explicit && !settings.implicit)
    throw Error("penalty renderer: an implicit coupling integration needs the implicit step");
  if (settings.couplingIntegration == CouplingIntegration::ImplicitWithDevice)
    checkCouplingDeviceModel(settings.deviceModel);
  m_state.worldFromBody = worldFromBodyStart;
  m_fieldMotion = FieldMotion::fixed(worldFromSdf);
  m_query.penalty = settings.contact;
  m_query.discreteMode = CcdMode::FirstHit;  // the points inside at the end pose; their intervals are not used
  m_query.method = settings.ccdMethod;
  m_query.octree = settings.octree;
  m_query.threads = settings.threads;
  // The every-contact query starts from the last tick's front (rigid_ccd_coherence.h): the same contacts bit for
  // bit, fewer field lookups where the shell stays clear of the field between ticks.
  if (settings.coherentCcd && m_field != nullptr) {  // obstacles: each pair keeps its own history
    m_query.coherence = &m_coherence;
    m_coherence.axisCertificates = settings.axisCertificates;
    // Builds the history (per-node tables and a first front) with a zero-length query at the start pose, so that the
    // first tick of the loop does not pay for it (milliseconds at 25,000 points in the peg). Its result is not used.
    ContactQuerySettings warm = m_query;
    warm.integratePenalty = false;
    queryContacts(m_tree, *m_field, ShellMotion::fixed(worldFromBodyStart), m_fieldMotion, settings.timestep, warm,
                  m_contacts);
  }
}

template <class Field>
PenaltyStepResult PenaltyRenderer<Field>::step(const RigidBodyState& device) {
  PenaltyStepResult out;
  const double h = m_settings.timestep;
  const CouplingWrench coupling = couplingWrench(device, m_state, m_settings.coupling);
  out.wrenchOnDevice = coupling.onDevice;
  const Mat6 mass = massMatrix(m_settings.mass, worldInertia(m_state.worldFromBody, m_settings.inertiaDiagonal));
  const Vec6 force = coupling.onSimulation + m_contactWrench;
  const Vec6 v = m_state.twist();
  Vec6 dv;
  if (m_settings.couplingIntegration != CouplingIntegration::Explicit) {
    dv = coupledVelocityChange(device, coupling, mass, out);
  } else if (m_settings.implicit) {
    const Mat6 k = coupling.poseGradient + m_contactGradient;
    const Mat6 a = mass - h * coupling.twistGradient - (h * h) * k;
    dv = a.partialPivLu().solve(h * (force + h * (k * v)));
    if (!dv.allFinite()) dv = h * mass.inverse() * force;  // singular system: explicit fallback
  } else {
    dv = h * mass.ldlt().solve(force);
  }
  const RigidBodyState start = m_state;
  m_state.linearVelocity += dv.head<3>();
  m_state.angularVelocity += dv.tail<3>();
  Vec6 move;
  move << h * m_state.linearVelocity, h * m_state.angularVelocity;
  m_state.worldFromBody = displacePose(start.worldFromBody, move);

  // Contact during the step that was just taken.
  ShellMotion shell;
  shell.worldFromShellStart = start.worldFromBody;
  shell.worldFromShellEnd = m_state.worldFromBody;
  shell.velocity.linearStart = start.linearVelocity;
  shell.velocity.linearEnd = m_state.linearVelocity;
  shell.velocity.angularStart = start.angularVelocity;
  shell.velocity.angularEnd = m_state.angularVelocity;
  if (m_obstacles) return obstacleContacts(shell, out);
  queryContacts(m_tree, *m_field, shell, m_fieldMotion, h, m_query, m_contacts);
  out.segmentQueries = m_contacts.ccd.stats.segmentQueries;
  out.certifiedNodes = m_contacts.ccd.stats.certified;
  const PenaltyResult& penalty = m_contacts.penalty;
  m_contactWrench << penalty.forceOnShell, penalty.torqueOnShell;
  out.contactWrench = m_contactWrench;
  out.contactCount = penalty.contactCount;
  out.maxPenetration = penalty.maxPenetration;

  updateContactGradient();
  if (!m_state.worldFromBody.matrix().allFinite() || !m_state.twist().allFinite())
    throw Error("penalty renderer: the simulation diverged (non-finite state)");
  return out;
}

// The implicit coupling modes (implicit_coupling.h): the object's velocity change and the wrench to render.
template <class Field>
Vec6 PenaltyRenderer<Field>::coupledVelocityChange(const RigidBodyState& device, const CouplingWrench& coupling,
                                                   const Mat6& mass, PenaltyStepResult& out) const {
  CoupledStepInput in;
  in.integration = m_settings.couplingIntegration;
  in.timestep = m_settings.timestep;
  in.objectMass = mass;
  in.objectTwist = m_state.twist();
  in.contactWrench = m_contactWrench;
  in.contactGradient = m_contactGradient;
  in.coupling = &coupling;
  in.device = &device;
  in.deviceModel = &m_settings.deviceModel;
  const CoupledStep step = solveCoupledStep(in);
  if (!step.solved) {  // singular system: the explicit fallback of the default scheme
    out.wrenchOnDevice = coupling.onDevice;
    return m_settings.timestep * mass.inverse() * (coupling.onSimulation + m_contactWrench);
  }
  out.wrenchOnDevice = step.wrenchOnDevice;
  return step.objectVelocityChange;
}

namespace {

/// The field's gradient at `pointInSdf`, and for a grid field inside its box also phi there (`outDistance`, else
/// NaN) from the same cell lookup: GridField::gradient and ::distance interpolate that cell each, so the values
/// are bit-identical and a contact pays one lookup instead of two.
template <class Field>
Vec3 gradientWithDistance(const Field& field, const Vec3& pointInSdf, double& outDistance) {
  outDistance = std::numeric_limits<double>::quiet_NaN();
  if constexpr (std::is_same_v<Field, GridField>) {
    if (field.grid().contains(pointInSdf)) {
      Vec3 gradient;
      outDistance = field.grid().interpolate(pointInSdf, gradient);
      return gradient;
    }
  }
  return field.gradient(pointInSdf);
}

/// The cross-product matrix [v]x (so that [v]x w = v x w).
Mat3 cross(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

}  // namespace

template <class Field>
void PenaltyRenderer<Field>::updateContactGradient() {
  // d(contact wrench on the object) / d(object pose), at the new pose, summed over the points inside there (see the
  // file comment). Per point: force f = c u with c = -k d >= 0 (d = phi - sigma < 0) and u the force's direction,
  // handle r (centre of mass to the point), B = [I, -[r]x] (a pose change dx moves the point by B dx), g the world
  // gradient of phi (dd/dp = g). Then
  //   d f   = -k u g^T B dx + c du,      du = dtheta x u  (the shell normal turns with the object; the field's
  //                                                        gradient direction does not, its curvature is dropped)
  //   d tau = [r]x d f + dr x f,          dr x f = (dtheta x r) x f = [f]x [r]x dtheta   (the geometric term)
  // so K = -k B^T u g^T B + [[0, -[f]x], [0, -[r]x [f]x + [f]x [r]x]] (shell normal; without the c du terms for the
  // gradient direction). Not symmetric; the step solves it with LU. consistentGradient = false gives the symmetric
  // approximation -k B^T n n^T B with n the unit gradient (the force's direction and the torque's lever dropped),
  // Fig. 10b's comparison.
  m_contactGradient.setZero();
  const Rigid& sdfFromEnd = m_contacts.sdfFromShellEnd;
  const Mat3 worldFromSdfRotation = m_worldFromSdf.linear();
  const Mat3 worldFromBody = m_state.worldFromBody.linear();
  const double k = m_settings.contact.stiffness;
  const double sigma = m_settings.contact.sigma;
  const bool shellNormal = m_settings.contact.direction == PenaltyDirection::ShellNormal;
  const PointShell& shell = m_tree.shell();
  // Continuous model: every point the CCD found in contact during the step, not only those inside at its end. A
  // point that left contact during the step still pushes during the next one (its force is the step's average,
  // eq. 5); without its stiffness in the implicit solve that push is explicit, and once k h^2 / m exceeds ~1 it
  // throws the object out of the contact (the peg is ejected at 1.2e6 N/m). Its depth gradient is taken
  // at the end pose (phi is defined everywhere); its force-order terms below only when it is still inside.
  const bool everyContact = m_settings.contact.model == PenaltyModel::Continuous && m_settings.consistentGradient;
  for (const PointContact& c : m_contacts.ccd.contacts) {
    if (!(c.depthAtEnd < 0.0) && !(everyContact && !c.intervals.empty())) continue;
    const std::size_t i = static_cast<std::size_t>(c.point);
    const Vec3 pointInSdf = sdfFromEnd * shell.positions[i];
    double distance;  // phi at the point when the gradient's lookup gave it (NaN: not yet)
    const Vec3 gradient = worldFromSdfRotation * gradientWithDistance(*m_field, pointInSdf, distance);
    const double len = gradient.norm();
    if (!(len > tolerance::kMinDirectionLength)) continue;
    const Vec3 r = worldFromBody * shell.positions[i];
    Eigen::Matrix<double, 1, 6> gRow;  // g^T B
    gRow.head<3>() = gradient.transpose();
    gRow.tail<3>() = r.cross(gradient).transpose();
    if (!m_settings.consistentGradient) {
      gRow /= len;
      m_contactGradient.noalias() -= k * gRow.transpose() * gRow;
      continue;
    }
    const Vec3 u = shellNormal ? Vec3(-(worldFromBody * shell.normals[i])) : Vec3(gradient / len);
    Eigen::Matrix<double, 6, 1> uColumn;  // B^T u
    uColumn.head<3>() = u;
    uColumn.tail<3>() = r.cross(u);
    m_contactGradient.noalias() -= k * uColumn * gRow;
    const double depth = (std::isnan(distance) ? m_field->distance(pointInSdf) : distance) - sigma;
    if (!(depth < 0.0)) continue;
    const Vec3 f = (-k * depth) * u;
    m_contactGradient.bottomRightCorner<3, 3>() += cross(f) * cross(r);  // the geometric term of the torque
    if (shellNormal) {
      m_contactGradient.topRightCorner<3, 3>() -= cross(f);
      m_contactGradient.bottomRightCorner<3, 3>() -= cross(r) * cross(f);
    }
  }
}

template <class Field>
PenaltyStepResult PenaltyRenderer<Field>::obstacleContacts(const ShellMotion& shell, PenaltyStepResult out) {
  const double h = m_settings.timestep;
  m_obstacles->moveOver(m_obstacleTime, m_obstacleTime + h);
  m_obstacles->penalty(shell, h, m_query, m_settings.consistentGradient, m_obstacleSum);
  out.segmentQueries = m_obstacleSum.segmentQueries;
  m_contactWrench = m_obstacleSum.wrenchOnTool;
  out.contactWrench = m_contactWrench;
  out.contactCount = m_obstacleSum.contactCount;
  out.maxPenetration = m_obstacleSum.maxPenetration;
  m_contactGradient = m_obstacleSum.gradient;
  if (!m_state.worldFromBody.matrix().allFinite() || !m_state.twist().allFinite())
    throw Error("penalty renderer: the simulation diverged (non-finite state)");
  return out;
}

#define SDFCCD_INSTANTIATE_PENALTY_RENDERER(Field) template class PenaltyRenderer<Field>;
SDFCCD_FOR_EACH_FIELD(SDFCCD_INSTANTIATE_PENALTY_RENDERER)
#undef SDFCCD_INSTANTIATE_PENALTY_RENDERER

}  // namespace sdfccd::haptics
