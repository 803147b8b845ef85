/// @file
/// @brief PenaltyRenderer: penalty-based 6-DoF haptic rendering with continuous (or discrete) contact and a
/// saturating virtual coupling, integrated implicitly (paper Section 4.1).
///
/// @details The simulated object (mass, inertia; frame origin at its centre of mass) carries the point shell
/// and is joined to the device by the virtual coupling (virtual_coupling.h). One haptic tick of length h:
///   1. the coupling wrench and its 6x6 gradients at the start of the tick;
///   2. one linearized backward Euler step (Baraff-Witkin style):
///        (M - h D - h^2 K) dv = h (F + h K v),  v += dv,  x += h v
///      with F = coupling + the contact wrench of the previous tick (eq. 5: the average contact force over
///      the last step acts during the next), K = coupling + contact stiffness gradients, D = coupling damping;
///   3. the CCD of the shell from the old to the new pose (AllIntervals, octree Leaves: the paper's choice at
///      haptic rates), then integratePenalty (penalty_model.h) gives the contact wrench of this step
///      (continuous: eqs. 3-5 over the contact sub-intervals; discrete: depth at the end pose only);
///   4. the contact gradient for the next tick: each point penetrating at the new pose contributes
///      -k B^T n n^T B (n the unit field gradient, B = [I, -[r]x] maps the body's twist to the point's motion),
///      the symmetric part of d(force)/d(pose) (the geometric term of the torque is dropped: it is not
///      symmetric and small at haptic penetrations);
///   5. the device feels the reaction of the coupling.
/// The device itself is integrated by the DeviceEmulator (explicit, at the same rate): the coupling force it
/// receives is bounded by F_max, so that step stays stable.
///
/// Thread safety: one renderer per haptic thread; the tree and the field are only read.
#pragma once

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sdfccd/error.h"
#include "sdfccd/haptics/rigid_body_state.h"
#include "sdfccd/haptics/spatial_types.h"
#include "sdfccd/haptics/virtual_coupling.h"
#include "sdfccd/math_types.h"
#include "sdfccd/response/penalty_model.h"
#include "sdfccd/shell/point_tree.h"
#include "sdfccd/ccd/rigid_ccd.h"

namespace sdfccd::haptics {

/// Settings of the penalty renderer.
struct PenaltyRendererSettings {
  PenaltySettings contact;           ///< the penalty model (stiffness per point, damping, continuous/discrete)
  VirtualCouplingSettings coupling;  ///< the device <-> object spring
  double mass = 0.1;                 ///< kg, the simulated object
  Vec3 inertiaDiagonal = Vec3::Constant(1e-4);  ///< kg m^2, body axes
  double timestep = 1e-3;                       ///< s, the haptic tick
  OctreeMode octree = OctreeMode::Leaves;
  CcdMethod ccdMethod = CcdMethod::Exact;
  int threads = 1;       ///< CCD worker threads
  bool implicit = true;  ///< false: symplectic Euler (for comparison)
};

/// What one tick did.
struct PenaltyStepResult {
  Vec6 wrenchOnDevice = Vec6::Zero();  ///< N, N m (the coupling's reaction)
  Vec6 contactWrench = Vec6::Zero();   ///< N, N m on the object, to act during the next tick
  int contactCount = 0;                ///< points that produced a force this tick
  double maxPenetration = 0.0;         ///< deepest sample this tick (model units, >= 0)
  std::int64_t segmentQueries = 0;
};

template <class Field>
class PenaltyRenderer {
 public:
  PenaltyRenderer(const PointTree& tree, const Field& field, const Rigid& worldFromSdf, const Rigid& worldFromBodyStart,
                  const PenaltyRendererSettings& settings)
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
    m_fieldMotion = PenaltyBodyMotion::fixed(worldFromSdf);
  }

  /// One haptic tick against the device state.
  PenaltyStepResult step(const RigidBodyState& device) {
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
    const Rigid sdfFromStart = m_sdfFromWorld * start.worldFromBody;
    const Rigid sdfFromEnd = m_sdfFromWorld * m_state.worldFromBody;
    const bool continuous = m_settings.contact.model == PenaltyModel::Continuous;
    RigidCcdSettings ccd;
    ccd.sigma = m_settings.contact.sigma;
    ccd.mode = continuous ? CcdMode::AllIntervals : CcdMode::FirstHit;
    ccd.method = m_settings.ccdMethod;
    ccd.octree = m_settings.octree;
    ccd.threads = m_settings.threads;
    rigidCcd(m_tree, m_field, continuous ? sdfFromStart : sdfFromEnd, sdfFromEnd, ccd, m_ccd);
    out.segmentQueries = m_ccd.stats.segmentQueries;
    PenaltyBodyMotion shell;
    shell.worldFromBodyStart = start.worldFromBody;
    shell.worldFromBodyEnd = m_state.worldFromBody;
    shell.linearVelocityStart = start.linearVelocity;
    shell.linearVelocityEnd = m_state.linearVelocity;
    shell.angularVelocityStart = start.angularVelocity;
    shell.angularVelocityEnd = m_state.angularVelocity;
    const PenaltyResult penalty =
        integratePenalty(m_tree.shell().positions, m_field, m_ccd, shell, m_fieldMotion, h, m_settings.contact);
    m_contactWrench << penalty.forceOnShell, penalty.torqueOnShell;
    out.contactWrench = m_contactWrench;
    out.contactCount = penalty.contactCount;
    out.maxPenetration = penalty.maxPenetration;

    // Contact stiffness at the new pose, for the next tick.
    m_contactGradient.setZero();
    const Mat3 worldFromSdfRotation = m_worldFromSdf.linear();
    const double k = m_settings.contact.stiffness;
    for (const PointContact& c : m_ccd.contacts) {
      if (!(c.depthAtEnd < 0.0)) continue;
      const Vec3 pointInShell = m_tree.shell().positions[static_cast<std::size_t>(c.point)];
      const Vec3 gradient = worldFromSdfRotation * m_field.gradient(sdfFromEnd * pointInShell);
      const double len = gradient.norm();
      if (!(len > 1e-12)) continue;
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

  const RigidBodyState& state() const { return m_state; }
  const PenaltyRendererSettings& settings() const { return m_settings; }
  Rigid sdfFromBody() const { return m_sdfFromWorld * m_state.worldFromBody; }

 private:
  const PointTree& m_tree;
  const Field& m_field;
  Rigid m_worldFromSdf;
  Rigid m_sdfFromWorld;
  PenaltyRendererSettings m_settings;
  RigidBodyState m_state;
  PenaltyBodyMotion m_fieldMotion;
  Vec6 m_contactWrench = Vec6::Zero();
  Mat6 m_contactGradient = Mat6::Zero();
  RigidCcdResult m_ccd;
};

}  // namespace sdfccd::haptics
