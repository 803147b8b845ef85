/// @file
/// @brief PenaltyRenderer: one haptic tick of penalty rendering (Section 4.1; see penalty_renderer.h). The contact
/// queries and gradients of steps 3 and 4 are the obstacles' (contact/obstacle_pair.h).
#include "sdfccd/haptics/penalty_renderer.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <utility>

#include "sdfccd/error.h"

namespace sdfccd::haptics {

PenaltyRenderer::PenaltyRenderer(ObstacleContacts contacts, const Rigid& worldFromBodyStart,
                                 const PenaltyRendererSettings& settings)
    : m_obstacles(std::move(contacts)), m_settings(settings) {
  const auto finitePositive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!finitePositive(settings.mass) || !finitePositive(settings.inertiaDiagonal.minCoeff()) ||
      !settings.inertiaDiagonal.allFinite() || !finitePositive(settings.timestep))
    throw Error("penalty renderer: mass, inertia and timestep must be positive and finite");
  if (!worldFromBodyStart.matrix().allFinite()) throw Error("penalty renderer: non-finite pose");
  if (settings.couplingIntegration != CouplingIntegration::Explicit && !settings.implicit)
    throw Error("penalty renderer: an implicit coupling integration needs the implicit step");
  if (settings.couplingIntegration == CouplingIntegration::ImplicitWithDevice)
    checkCouplingDeviceModel(settings.deviceModel);
  m_state.worldFromBody = worldFromBodyStart;
  m_query.penalty = settings.contact;
  m_query.discreteMode = CcdMode::FirstHit;  // the points inside at the end pose; their intervals are not used
  m_query.method = settings.ccdMethod;
  m_query.octree = settings.octree;
  m_query.threads = settings.threads;
  m_obstacles.prepare(m_settings, m_query, worldFromBodyStart);
}

PenaltyStepResult PenaltyRenderer::step(const RigidBodyState& device) {
  PenaltyStepResult out;
  const double h = m_settings.timestep;
  const CouplingWrench coupling = couplingWrench(device, m_state, m_settings.coupling);
  out.wrenchOnDevice = coupling.onDevice;
  const Mat6 mass = massMatrix(m_settings.mass, worldInertia(m_state.worldFromBody, m_settings.inertiaDiagonal));
  const Vec6 dv = velocityChange(device, coupling, mass, out);
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
  return contactsOver(shell, out);
}

// Step 2: (M - h D - h^2 K) dv = h (F + h K v) with the coupling frozen for the tick, or symplectic Euler, or the
// implicit coupling modes.
Vec6 PenaltyRenderer::velocityChange(const RigidBodyState& device, const CouplingWrench& coupling, const Mat6& mass,
                                     PenaltyStepResult& out) const {
  const double h = m_settings.timestep;
  const Vec6 force = coupling.onSimulation + m_contactWrench;
  if (m_settings.couplingIntegration != CouplingIntegration::Explicit)
    return coupledVelocityChange(device, coupling, mass, out);
  if (!m_settings.implicit) return h * mass.ldlt().solve(force);
  const Vec6 v = m_state.twist();
  const Mat6 k = coupling.poseGradient + m_contactGradient;
  const Mat6 a = mass - h * coupling.twistGradient - (h * h) * k;
  Vec6 dv = a.partialPivLu().solve(h * (force + h * (k * v)));
  if (!dv.allFinite()) dv = h * mass.inverse() * force;  // singular system: explicit fallback
  return dv;
}

// The implicit coupling modes (implicit_coupling.h): the object's velocity change and the wrench to render.
Vec6 PenaltyRenderer::coupledVelocityChange(const RigidBodyState& device, const CouplingWrench& coupling,
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

PenaltyStepResult PenaltyRenderer::contactsOver(const ShellMotion& shell, PenaltyStepResult out) {
  const double h = m_settings.timestep;
  m_obstacles.moveOver(m_obstacleTime, m_obstacleTime + h);
  m_obstacles.penalty(shell, h, m_query, m_settings.consistentGradient, m_obstacleSum);
  out.segmentQueries = m_obstacleSum.segmentQueries;
  out.certifiedNodes = m_obstacleSum.certifiedNodes;
  m_contactWrench = m_obstacleSum.wrenchOnTool;
  out.contactWrench = m_contactWrench;
  out.contactCount = m_obstacleSum.contactCount;
  out.maxPenetration = m_obstacleSum.maxPenetration;
  m_contactGradient = m_obstacleSum.gradient;
  if (!m_state.worldFromBody.matrix().allFinite() || !m_state.twist().allFinite())
    throw Error("penalty renderer: the simulation diverged (non-finite state)");
  return out;
}

}  // namespace sdfccd::haptics
