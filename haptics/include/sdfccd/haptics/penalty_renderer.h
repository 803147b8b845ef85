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
///   3. queryContacts (contact_query.h): the CCD of the shell from the old to the new pose (AllIntervals,
///      octree Leaves: the paper's choice at haptic rates) and the penalty model on it give the contact wrench
///      of this step (continuous: eqs. 3-5 over the contact sub-intervals; discrete: depth at the end pose
///      only, the CCD in FirstHit mode there);
///   4. the contact gradient for the next tick, d(contact wrench)/d(pose) at the new pose: each point penetrating
///      there contributes -k B^T u g^T B (u the direction its force takes, the same as the penalty model's: the
///      shell's normal by default; g the field's gradient, the derivative of its depth; B = [I, -[r]x] maps a pose
///      change to the point's motion), plus the terms of order of its force: the shell normal turning with the
///      object, and the geometric term of the torque (the lever r turning). Not symmetric: LU solve;
///      consistentGradient = false: the symmetric -k B^T n n^T B (n the unit gradient), for comparison;
///   5. the device feels the reaction of the coupling.
/// The device itself is integrated by the DeviceEmulator (explicit, at the same rate): the coupling force it
/// receives is bounded by F_max, so that step stays stable. Step 2 and the reaction of step 5 are, by default,
/// those of the device frozen for the tick (CouplingIntegration::Explicit); the implicit modes of
/// implicit_coupling.h integrate the coupling with the object (and with the device's model where it is known).
///
/// Frames: the shell frame is the simulated object's body frame, its origin the centre of mass. Contacts: steps 3 and
/// 4 are every obstacle's query and gradient over the tick's relative motion (ObstacleContacts, haptic_obstacles.h):
/// the scene's one static field is an obstacle with a fixed pose, whose query starts from the last tick's CCD front
/// (coherentCcd); a moving obstacle's wrench is fed forward by its own motion (ObstacleContacts::penalty).
///
/// Thread safety: one renderer per haptic thread; the trees and fields are only read.
#pragma once

#include <cstdint>

#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/haptics/haptic_obstacles.h"
#include "sdfccd/haptics/implicit_coupling.h"
#include "sdfccd/haptics/rigid_body_state.h"
#include "sdfccd/haptics/spatial_types.h"
#include "sdfccd/haptics/virtual_coupling.h"
#include "sdfccd/math_types.h"
#include "sdfccd/response/contact_query.h"
#include "sdfccd/response/penalty_model.h"
#include "sdfccd/shell/point_tree.h"

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
  /// The contact gradient with the force's own direction and the torque's geometric term (see step 4); false: the
  /// symmetric field-normal approximation (for comparison, Fig. 10b).
  bool consistentGradient = true;
  /// The CCD started from the last tick's front (temporal coherence, rigid_ccd_coherence.h): the contacts are the
  /// fresh query's bit for bit; false: the fresh query every tick (for comparison).
  bool coherentCcd = true;
  /// With coherentCcd: certificates that split the motion per axis of the field (axis_lipschitz_bounds.h), so that
  /// sliding along an axis-aligned wall does not use up a point's clearance; the same contacts bit for bit.
  bool axisCertificates = true;
  /// How the coupling enters the step and what the device is rendered (implicit_coupling.h): Explicit (default:
  /// the device frozen for the tick, rendered the coupling at the tick's start), Implicit (the
  /// paper's admittance mode: rendered the coupling at the end of the object's implicit step) or ImplicitWithDevice
  /// (the device's dynamics, `deviceModel`, in the same backward Euler step). Both implicit modes need `implicit`.
  CouplingIntegration couplingIntegration = CouplingIntegration::Explicit;
  CouplingDeviceModel deviceModel;  ///< ImplicitWithDevice: the device's mass, inertia, friction
};

/// What one tick did.
struct PenaltyStepResult {
  Vec6 wrenchOnDevice = Vec6::Zero();  ///< N, N m (the coupling's reaction)
  Vec6 contactWrench = Vec6::Zero();   ///< N, N m on the object, to act during the next tick
  int contactCount = 0;                ///< points that produced a force this tick
  double maxPenetration = 0.0;         ///< deepest sample this tick (model units, >= 0)
  std::int64_t segmentQueries = 0;
  std::int64_t certifiedNodes = 0;  ///< coherent CCD: tree nodes ruled out by their certificate alone
};

/// The renderer of one simulated object against the obstacles of its contact source.
class PenaltyRenderer {
 public:
  /// `contacts`: the obstacles, the object's shell among them (one static field at a fixed pose, or several, static
  /// or moving; each tick's contacts are over the relative motion of [time, time + timestep], setObstacleTime); the
  /// renderer owns it. `worldFromBodyStart` places the object. Throws sdfccd::Error on bad settings or a non-finite
  /// pose.
  PenaltyRenderer(ObstacleContacts contacts, const Rigid& worldFromBodyStart, const PenaltyRendererSettings& settings);

  /// The time (s) at the start of the next tick (the obstacles move over [time, time + timestep]).
  void setObstacleTime(double time) { m_obstacleTime = time; }

  /// One haptic tick against the device state.
  PenaltyStepResult step(const RigidBodyState& device);

  const RigidBodyState& state() const { return m_state; }
  const PenaltyRendererSettings& settings() const { return m_settings; }
  /// d(contact wrench)/d(pose) at the current pose, used by the next step (N/m, N, N m blocks).
  const Mat6& contactGradient() const { return m_contactGradient; }
  /// The deepest penetration (phi < 0) of any obstacle pair at the object's pose (model units, >= 0).
  double penetration() { return m_obstacles.penetration(m_state.worldFromBody); }

 private:
  /// The velocity change of the tick (steps 1 and 2): explicit, implicit with the coupling frozen, or one of the
  /// implicit coupling modes (`out` gets the wrench to render).
  Vec6 velocityChange(const RigidBodyState& device, const CouplingWrench& coupling, const Mat6& mass,
                      PenaltyStepResult& out) const;
  Vec6 coupledVelocityChange(const RigidBodyState& device, const CouplingWrench& coupling, const Mat6& mass,
                             PenaltyStepResult& out) const;
  /// Steps 3 and 4: the obstacles' contacts over the step just taken (`shell`: the object's motion): wrench,
  /// gradient, result.
  PenaltyStepResult contactsOver(const ShellMotion& shell, PenaltyStepResult out);

  ObstacleContacts m_obstacles;
  double m_obstacleTime = 0.0;  // s
  ObstaclePenaltySum m_obstacleSum;
  PenaltyRendererSettings m_settings;
  RigidBodyState m_state;
  ContactQuerySettings m_query;
  Vec6 m_contactWrench = Vec6::Zero();
  Mat6 m_contactGradient = Mat6::Zero();
};

}  // namespace sdfccd::haptics
