/// @file
/// @brief The continuous penalty model (paper Section 4.1, eqs. 3-5) and its discrete baseline.
///
/// @details One shell body's points move against another body's distance field during a step of length dt.
/// The rigid CCD (rigid_ccd.h, AllIntervals mode) gives, for every point in contact, the sub-intervals of the
/// step where phi <= sigma. Over each sub-interval the penalty force and its torque are integrated with the
/// midpoint rule on `subintervals` equal pieces (eqs. 3, 4):
///   I = sum_i int -k d(t) N(t) dt,    M = -sum_i int r(t) x (k d(t) N(t)) dt,
/// and their averages F* = I / dt, tau* = M / dt (eq. 5) act over the next step.
///
/// Conventions (decided here):
/// - Frames: the shell body moves as worldFromShellStart -> worldFromShellEnd (its points' frame), the field
///   body as worldFromSdfStart -> worldFromSdfEnd (the field's frame); contact_query.h runs the CCD and this
///   model on these same frames.
/// - d(t) = phi(p(t)) - sigma, with p(t) the point's linear trajectory in the field's frame between its start
///   and end positions, the segment the CCD tested. The ends are computed through world,
///   sdfFromWorld * (worldFromShell * x), where the CCD uses (sdfFromWorld * worldFromShell) * x: the same
///   segment up to rounding (kept so, bit for bit, until the contact-response rebuild). Only d < 0 pushes.
/// - N(t) is the point's outward normal in world, linearly interpolated between its start and end directions
///   and normalized; the force from the depth comes from the shell's normal, not the field's gradient, so it
///   stays continuous when a point crosses the field's medial axis (Section 4.1). That force is not
///   conservative: where a point's normal is not opposite the field's gradient (a shell point on a box's
///   edge or corner resting on the ground) it pushes sideways, and a resting body drifts, spins up and can
///   gain energy (tests/bullet/stability_test.cpp). PenaltyDirection::FieldGradient (beyond the paper) uses
///   N(t) = -grad phi / |grad phi| at the sample instead: F = -k d grad phi is minus the gradient of the
///   energy k d^2 / 2, so contact forces alone never add energy; the shell normal is the fallback where
///   the gradient vanishes.
/// - The field body receives F(t) = (k |d| + c v_n) N(t); the shell body receives -F(t). v_n is the normal
///   velocity of the shell's point relative to the field body's material point at the same place, positive
///   when approaching (along N). The total normal force is clamped at zero: damping never pulls bodies together.
///   Per-area law in the continuous model (dampingPerStiffness, c_i = beta k_i): the pair's damping is Rayleigh
///   damping of its elastic wrench W, beta dW/dt: each point's damper is unclamped, the torque gets the lever term
///   beta (dh/dt x k |d| N) of the handles that move with the point, and the clamp is the pair's (damping never
///   cancels more than the elastic impulse along its direction). A steady patch travelling through a rolling
///   shell is then not damped (penalty_model.cpp, PairDamping).
/// - Handles r(t) go from each body's centre of mass to the point; they and the velocities are linear in t.
/// - Damping integrals are only evaluated when enableDamping is set (and damping > 0); torques only when
///   enableRotation is set: effects a scene does not ask for cost nothing.
/// - Discrete baseline: the depth at the step's end only, F = -k d N at the end pose, as if constant over the
///   step (impulse F dt).
#pragma once

#include <cstdint>
#include <vector>

#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/math_types.h"
#include "sdfccd/response/contact_material.h"
#include "sdfccd/response/friction_anchor.h"

namespace sdfccd {

/// Which penalty model integrates the contact.
enum class PenaltyModel : std::uint8_t {
  Continuous,  ///< eqs. (3)-(5) over the CCD's contact sub-intervals
  Discrete,    ///< depth at the end of the step only (the baseline of Fig. 10a)
};

/// Which direction the penalty force takes (see the file comment).
enum class PenaltyDirection : std::uint8_t {
  ShellNormal,    ///< the shell point's outward normal (paper, Section 4.1)
  FieldGradient,  ///< minus the field's normalized gradient at the point: conservative (beyond the paper)
  /// The gradient while shallow, blended to the shell normal between blendStartCells and blendEndCells of depth
  /// (smoothstep): conservative in resting and sliding contact, the paper's direction in deep impacts
  /// (docs/design/contact-response.md, force direction).
  Blend,
};

/// Which tangential law friction follows.
enum class FrictionModel : std::uint8_t {
  Regularized,  ///< |F_t| = mu F_n min(1, |v_t| / frictionSlipSpeed): creeps below atan mu (paper-like runs)
  Anchor,       ///< stick-slip anchor per shell point (friction_anchor.h): holds below atan mu, exact Coulomb above
};

/// Settings of the penalty model.
struct PenaltySettings {
  PenaltyModel model = PenaltyModel::Continuous;
  double stiffness = 2000.0;   ///< k, N/m (per point)
  double damping = 0.0;        ///< c, N s/m (per point)
  int subintervals = 5;        ///< midpoint-rule pieces per contact sub-interval (paper: 5)
  bool enableDamping = true;   ///< integrate damping impulses (needs damping > 0 as well)
  bool enableRotation = true;  ///< integrate angular impulses (torques)
  /// Beyond the paper: regularized Coulomb friction, |F_t| = mu |F_n| min(1, |v_t| / frictionSlipSpeed),
  /// opposing the tangential velocity of the point relative to the field body. Evaluated only when
  /// enableFriction is set and friction > 0.
  bool enableFriction = false;
  double friction = 0.0;            ///< mu, Coulomb coefficient (dimensionless)
  double frictionSlipSpeed = 0.01;  ///< m/s; below it friction is viscous (keeps the explicit step stable)
  double sigma = 0.0;               ///< contact level set (model units); the CCD must use the same value
  PenaltyDirection direction = PenaltyDirection::ShellNormal;  ///< force direction (see the file comment)
  double blendStartCells = 1.0;  ///< Blend: depth (field cells) where the shell normal starts to take over
  double blendEndCells = 2.0;    ///< Blend: depth (field cells) from which the shell normal alone is used
  FrictionModel frictionModel = FrictionModel::Regularized;  ///< tangential law (with enableFriction)
  /// Stiffness per unit shell area k_A (N/m^3; docs/design/contact-response.md). > 0: k_i = s_r k_A A_i from the
  /// shell's point areas (s_r = roleScale), capped per pair and step (caps), and `stiffness` is not used. 0: the
  /// paper's per-point `stiffness`, uncapped.
  double stiffnessPerArea = 0.0;
  double roleScale = 1.0;  ///< s_r: 1/2 when the pair runs both roles (each interface counted twice), else 1
  /// Damping from a damping ratio zeta (dimensionless, [0, 2]) of the pair's spring (contact_material.h):
  /// c_i = 2 zeta k_i sqrt(m_eff / K), capped. Needs the bodies' masses (ShellMotion/FieldMotion); < 0: the
  /// per-point `damping`.
  double dampingRatio = -1.0;
  /// Bullet: zeta = zeta(e) of the pair's combined restitution (contact_material.h), replacing dampingRatio.
  bool dampingRatioFromRestitution = false;
  /// Bullet: mu = the pair's combined friction (gCalculateCombinedFrictionCallback), replacing `friction`.
  bool frictionFromBodies = false;
  StabilityCapSettings caps;  ///< per-area law only: omega dt and C dt / m_eff caps per pair and step

  /// The defaults of new Bullet worlds and scenes: k_A = 1e7 N/m^3, zeta = 1 (Bullet: from the pair's
  /// restitution), Blend direction, anchor friction on, mu = 0.5 until the pair's material says otherwise.
  static PenaltySettings trustworthy() {
    PenaltySettings s;
    s.stiffnessPerArea = 1.0e7;
    s.dampingRatio = 1.0;
    s.dampingRatioFromRestitution = true;
    s.frictionFromBodies = true;
    s.direction = PenaltyDirection::Blend;
    s.frictionModel = FrictionModel::Anchor;
    s.enableFriction = true;
    s.friction = 0.5;
    return s;
  }
};

/// How a body's centre of mass moves during the step: velocities linear in t between start and end.
struct BodyVelocities {
  Vec3 linearStart = Vec3::Zero();   ///< velocity of the centre of mass, world (m/s)
  Vec3 linearEnd = Vec3::Zero();     ///< m/s
  Vec3 angularStart = Vec3::Zero();  ///< world (rad/s)
  Vec3 angularEnd = Vec3::Zero();    ///< rad/s

  bool allFinite() const {
    return linearStart.allFinite() && linearEnd.allFinite() && angularStart.allFinite() && angularEnd.allFinite();
  }
};

/// A body's inverse mass properties for the per-pair caps (zero: static, kinematic or asleep: infinite mass).
struct BodyInverseMass {
  double inverseMass = 0.0;                   ///< 1/kg
  Mat3 inverseInertiaInWorld = Mat3::Zero();  ///< 1/(kg m^2), world, at the step's start
};

/// The motion of the shell body during the step, in the frame of its points.
struct ShellMotion {
  Rigid worldFromShellStart = Rigid::Identity();
  Rigid worldFromShellEnd = Rigid::Identity();
  Vec3 centerOfMassInShell = Vec3::Zero();  ///< model units
  BodyVelocities velocity;
  BodyInverseMass mass;  ///< for the caps and the damping ratio (per-area law)

  /// A shell that does not move.
  static ShellMotion fixed(const Rigid& worldFromShell) {
    ShellMotion m;
    m.worldFromShellStart = worldFromShell;
    m.worldFromShellEnd = worldFromShell;
    return m;
  }
};

/// The motion of the field body during the step, in the field's frame (a model's field frame need not be its
/// body frame: centerOfMassInSdf says where the body's centre of mass is).
struct FieldMotion {
  Rigid worldFromSdfStart = Rigid::Identity();
  Rigid worldFromSdfEnd = Rigid::Identity();
  Vec3 centerOfMassInSdf = Vec3::Zero();  ///< model units
  BodyVelocities velocity;
  BodyInverseMass mass;  ///< for the caps and the damping ratio (per-area law)

  /// A field that does not move (a static ground, a fixed obstacle).
  static FieldMotion fixed(const Rigid& worldFromSdf) {
    FieldMotion m;
    m.worldFromSdfStart = worldFromSdf;
    m.worldFromSdfEnd = worldFromSdf;
    return m;
  }
};

/// What the model produced for one (shell body, field body) pair over one step.
struct PenaltyResult {
  Vec3 impulseOnShell = Vec3::Zero();         ///< N s, world
  Vec3 angularImpulseOnShell = Vec3::Zero();  ///< N m s, about the shell body's centre of mass, world
  Vec3 impulseOnField = Vec3::Zero();         ///< N s
  Vec3 angularImpulseOnField = Vec3::Zero();  ///< N m s, about the field body's centre of mass
  Vec3 forceOnShell = Vec3::Zero();           ///< eq. (5): impulse / dt (N)
  Vec3 torqueOnShell = Vec3::Zero();          ///< angular impulse / dt (N m)
  Vec3 forceOnField = Vec3::Zero();           ///< N
  Vec3 torqueOnField = Vec3::Zero();          ///< N m
  double maxPenetration = 0.0;                ///< largest -d seen at a sample (model units, >= 0)
  int contactCount = 0;                       ///< points that produced a force
  /// Work counters (the report's proof that an effect not asked for costs nothing): samples in contact, and
  /// of them those that evaluated the damping term, the torques, the friction term.
  std::int64_t samples = 0;
  std::int64_t dampingEvaluations = 0;
  std::int64_t torqueEvaluations = 0;
  std::int64_t frictionEvaluations = 0;
  bool stiffnessCapped = false;  ///< per-area law: the omega dt cap softened this pair (contact_material.h)
  int slippingPoints = 0;        ///< anchor friction: points whose anchor slipped at the step's end
};

/// What a pair's role brings to the integrals beyond the settings (per-area law, blend band, anchors).
struct PenaltyRoleInput {
  const std::vector<double>* areas = nullptr;  ///< the shell's point areas (m^2), per-area law
  double stiffnessPerArea = 0.0;               ///< N/m^3 after s_r and the cap: k_i = this A_i (0: per point)
  double dampingPerStiffness = -1.0;           ///< s: c_i = this k_i (< 0: the per-point `damping`)
  double cellSize = 0.0;                       ///< the field's cell (model units): the Blend band
  /// The shell's curvature per point (PointTree::curvatures); null: every direction from the field alone. With
  /// it, a contact's direction leans to the shell's normal where the field is the more curved surface
  /// (contact_normal.h), over the whole step.
  const std::vector<double>* curvatures = nullptr;
  FrictionAnchorTable* anchors = nullptr;      ///< io: this pair and role's anchors (FrictionModel::Anchor)
};

/// The per-area law's coefficients for one pair and role (stiffness per area, caps): sums k_i = s_r k_A A_i over the
/// contacts, takes m_eff along the contacts' mean field normal at their centroid and applies the caps
/// (contact_material.h). `pairStiffnessFactor` turns the role's K into the pair's (1 / s_r: the other role
/// is taken as its mirror). Fills `io.stiffnessPerArea` and `io.dampingPerStiffness`; returns the caps' result.
template <class Field>
PairResponseCoefficients perAreaCoefficients(const std::vector<Vec3>& pointsInShell, const Field& field,
                                             const RigidCcdResult& ccd, const ShellMotion& shell,
                                             const FieldMotion& fieldBody, double timestep,
                                             const PenaltySettings& settings, PenaltyRoleInput& io);

/// Integrates the penalty impulses of one (shell body, field body) pair over a step of `timestep` seconds.
/// `pointsInShell` are the shell's points (the indices of `ccd.contacts` refer to them); each contact's
/// `pointNormalInShell` gives its normal. Continuous: uses each contact's intervals (run the CCD with
/// CcdMode::AllIntervals). Discrete: ignores the intervals and evaluates every listed contact at the end pose
/// (run the CCD with start = end so that it lists the points inside at the end). `Field` is one of the field
/// types of field_interface.h (defined in penalty_model.cpp). Throws sdfccd::Error on a bad timestep, bad
/// settings or a bad point index. contact_query.h runs the CCD and this on one frame contract.
template <class Field>
PenaltyResult integratePenalty(const std::vector<Vec3>& pointsInShell, const Field& field, const RigidCcdResult& ccd,
                               const ShellMotion& shell, const FieldMotion& fieldBody, double timestep,
                               const PenaltySettings& settings);

/// The same with the role's input (per-area stiffness, damping per stiffness, blend band, anchors).
template <class Field>
PenaltyResult integratePenalty(const std::vector<Vec3>& pointsInShell, const Field& field, const RigidCcdResult& ccd,
                               const ShellMotion& shell, const FieldMotion& fieldBody, double timestep,
                               const PenaltySettings& settings, const PenaltyRoleInput& input);

/// perAreaCoefficients (into `outCoefficients`), then integratePenalty with the input it filled: what queryContacts
/// runs. Bit for bit the two calls' results, cheaper with anchor friction: the gradient perAreaCoefficients takes at
/// each contact's end position and phi there, from the same cell lookup, serve the anchors' end-of-step update.
template <class Field>
PenaltyResult integratePenaltyWithCoefficients(const std::vector<Vec3>& pointsInShell, const Field& field,
                                               const RigidCcdResult& ccd, const ShellMotion& shell,
                                               const FieldMotion& fieldBody, double timestep,
                                               const PenaltySettings& settings, PenaltyRoleInput& io,
                                               PairResponseCoefficients& outCoefficients);

/// The checks of integratePenalty (throws sdfccd::Error).
void checkPenaltyInput(std::size_t pointCount, const RigidCcdResult& ccd, double timestep,
                       const PenaltySettings& settings);

}  // namespace sdfccd
