/// @file
/// @brief PenaltyRenderer: one haptic tick of penalty rendering (Section 4.1; see penalty_renderer.h),
/// instantiated for every field type of field_interface.h.
#include "sdfccd/haptics/penalty_renderer.h"

#include <Eigen/LU>
#include <cmath>

#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/tolerances.h"

namespace sdfccd::haptics {

template <class Field>
PenaltyRenderer<Field>::PenaltyRenderer(const PointTree& tree, const Field& field, const Rigid& worldFromSdf,
                                        const Rigid& worldFromBodyStart, const PenaltyRendererSettings& settings)
    : m_tree(tree),
      m_field(field),
      m_worldFromSdf(worldFromSdf),
      m_sdfFromWorld(worldFromSdf.inverse()),
      m_settings(settings) {
  const auto finitePositive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!finitePositive(settings.mass) || !finitePositive(settings.inertiaDiagonal.minCoeff()) ||
      !settings.inertiaDiagonal.allFinite() || !finitePositive(settings.timestep))
    throw Error("penalty renderer: mass, inertia and timestep must be positive and finite");
  if (!worldFromBodyStart.matrix().allFinite() || !worldFromSdf.matrix().allFinite())
    throw Error("penalty renderer: non-finite pose");
  m_state.worldFromBody = worldFromBodyStart;
  m_fieldMotion = FieldMotion::fixed(worldFromSdf);
  m_query.penalty = settings.contact;
  m_query.discreteMode = CcdMode::FirstHit;  // the points inside at the end pose; their intervals are not used
  m_query.method = settings.ccdMethod;
  m_query.octree = settings.octree;
  m_query.threads = settings.threads;
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
  if (m_settings.implicit) {
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
  queryContacts(m_tree, m_field, shell, m_fieldMotion, h, m_query, m_contacts);
  out.segmentQueries = m_contacts.ccd.stats.segmentQueries;
  const PenaltyResult& penalty = m_contacts.penalty;
  m_contactWrench << penalty.forceOnShell, penalty.torqueOnShell;
  out.contactWrench = m_contactWrench;
  out.contactCount = penalty.contactCount;
  out.maxPenetration = penalty.maxPenetration;

  // Contact stiffness at the new pose, for the next tick.
  m_contactGradient.setZero();
  const Rigid& sdfFromEnd = m_contacts.sdfFromShellEnd;
  const Mat3 worldFromSdfRotation = m_worldFromSdf.linear();
  const double k = m_settings.contact.stiffness;
  for (const PointContact& c : m_contacts.ccd.contacts) {
    if (!(c.depthAtEnd < 0.0)) continue;
    const Vec3 pointInShell = m_tree.shell().positions[static_cast<std::size_t>(c.point)];
    const Vec3 gradient = worldFromSdfRotation * m_field.gradient(sdfFromEnd * pointInShell);
    const double len = gradient.norm();
    if (!(len > tolerance::kMinDirectionLength)) continue;
    const Vec3 n = gradient / len;
    const Vec3 r = m_state.worldFromBody.linear() * pointInShell;
    Eigen::Matrix<double, 1, 6> row;  // n^T B
    row.head<3>() = n.transpose();
    row.tail<3>() = r.cross(n).transpose();
    m_contactGradient.noalias() -= k * row.transpose() * row;
  }
  if (!m_state.worldFromBody.matrix().allFinite() || !m_state.twist().allFinite())
    throw Error("penalty renderer: the simulation diverged (non-finite state)");
  return out;
}

#define SDFCCD_INSTANTIATE_PENALTY_RENDERER(Field) template class PenaltyRenderer<Field>;
SDFCCD_FOR_EACH_FIELD(SDFCCD_INSTANTIATE_PENALTY_RENDERER)
#undef SDFCCD_INSTANTIATE_PENALTY_RENDERER

}  // namespace sdfccd::haptics
