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
/// - d(t) = phi(p(t)) - sigma, with p(t) the point's linear trajectory in the field's frame between
///   sdfFromShellStart * x and sdfFromShellEnd * x (the same segment the CCD tested). Only d < 0 pushes.
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
/// - Handles r(t) go from each body's centre of mass to the point; they and the velocities are linear in t.
/// - Damping integrals are only evaluated when enableDamping is set (and damping > 0); torques only when
///   enableRotation is set: effects a scene does not ask for cost nothing.
/// - Discrete baseline: the depth at the step's end only, F = -k d N at the end pose, as if constant over the
///   step (impulse F dt).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/ccd/rigid_ccd.h"

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
};

/// The motion of one body during the step. Velocities are linear in t between start and end.
struct PenaltyBodyMotion {
  Rigid worldFromBodyStart = Rigid::Identity();
  Rigid worldFromBodyEnd = Rigid::Identity();
  Vec3 centerOfMassInBody = Vec3::Zero();    ///< model units
  Vec3 linearVelocityStart = Vec3::Zero();   ///< velocity of the centre of mass, world (m/s)
  Vec3 linearVelocityEnd = Vec3::Zero();     ///< m/s
  Vec3 angularVelocityStart = Vec3::Zero();  ///< world (rad/s)
  Vec3 angularVelocityEnd = Vec3::Zero();    ///< rad/s

  /// A body that does not move (a static ground, a fixed obstacle).
  static PenaltyBodyMotion fixed(const Rigid& worldFromBody) {
    PenaltyBodyMotion m;
    m.worldFromBodyStart = worldFromBody;
    m.worldFromBodyEnd = worldFromBody;
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
};

namespace detail {

/// Precomputed, per contact: the point's trajectory and what interpolates linearly in t.
struct PenaltyPointPath {
  Vec3 pointInSdfStart, pointInSdfEnd;        // field frame
  Vec3 normalInWorldStart, normalInWorldEnd;  // shell's outward normal
  Vec3 handleShellStart, handleShellEnd;      // world, from the shell body's COM to the point
  Vec3 handleFieldStart, handleFieldEnd;      // world, from the field body's COM to the point
  Mat3 worldFromSdfStart, worldFromSdfEnd;    // rotation of the field's frame (FieldGradient direction)
};

/// True when Field has `Vec3 gradient(const Vec3&) const` (FieldGradient needs it; ShellNormal does not).
template <class Field, class = void>
struct HasGradient : std::false_type {};
template <class Field>
struct HasGradient<Field, std::void_t<decltype(std::declval<const Field&>().gradient(Vec3()))>> : std::true_type {};

inline Vec3 lerp(const Vec3& a, const Vec3& b, double t) {
  return a + t * (b - a);
}

/// Adds the force at fraction t, weighted by `weight` seconds, to `io`. Returns the depth d (model units).
template <class Field>
double addPenaltySample(const Field& field, const PenaltyPointPath& path, const PenaltyBodyMotion& shell,
                        const PenaltyBodyMotion& fieldBody, double t, double weight, const PenaltySettings& settings,
                        bool useDamping, bool useFriction, PenaltyResult& io) {
  const double depth = field.distance(lerp(path.pointInSdfStart, path.pointInSdfEnd, t)) - settings.sigma;
  if (!(depth < 0.0)) return depth;
  Vec3 normal = lerp(path.normalInWorldStart, path.normalInWorldEnd, t);
  if constexpr (HasGradient<Field>::value) {
    if (settings.direction == PenaltyDirection::FieldGradient) {
      const Vec3 gradientInSdf = field.gradient(lerp(path.pointInSdfStart, path.pointInSdfEnd, t));
      const Vec3 away = -lerp(path.worldFromSdfStart * gradientInSdf, path.worldFromSdfEnd * gradientInSdf, t);
      if (away.allFinite() && away.norm() > 0.0) normal = away;  // else: the shell normal (a flat spot of phi)
    }
  }
  const double normalLength = normal.norm();
  if (!(normalLength > 0.0)) return depth;  // the normal turned half a turn during the step: no direction
  normal /= normalLength;
  ++io.samples;
  double magnitude = -settings.stiffness * depth;  // N
  const bool needVelocity = useDamping || useFriction;
  const bool needHandles = needVelocity || settings.enableRotation;
  Vec3 handleShell = Vec3::Zero();
  Vec3 handleField = Vec3::Zero();
  if (needHandles) {
    handleShell = lerp(path.handleShellStart, path.handleShellEnd, t);
    handleField = lerp(path.handleFieldStart, path.handleFieldEnd, t);
  }
  Vec3 relativeVelocity = Vec3::Zero();  // of the shell's point relative to the field body's material point
  if (needVelocity) {
    const Vec3 velocityShell = lerp(shell.linearVelocityStart, shell.linearVelocityEnd, t) +
                               lerp(shell.angularVelocityStart, shell.angularVelocityEnd, t).cross(handleShell);
    const Vec3 velocityField = lerp(fieldBody.linearVelocityStart, fieldBody.linearVelocityEnd, t) +
                               lerp(fieldBody.angularVelocityStart, fieldBody.angularVelocityEnd, t).cross(handleField);
    relativeVelocity = velocityShell - velocityField;
  }
  if (useDamping) {
    ++io.dampingEvaluations;
    const double approachSpeed = relativeVelocity.dot(normal);  // m/s, > 0 approaching
    magnitude = std::max(0.0, magnitude + settings.damping * approachSpeed);
  }
  Vec3 impulseOnField = (weight * magnitude) * normal;
  if (useFriction) {
    ++io.frictionEvaluations;
    // The field body drags the shell's point backwards: on the field, the force follows the slip.
    const Vec3 slip = relativeVelocity - relativeVelocity.dot(normal) * normal;
    const double slipSpeed = slip.norm();
    if (slipSpeed > 0.0) {
      const double scale = settings.friction * magnitude / std::max(slipSpeed, settings.frictionSlipSpeed);
      impulseOnField += (weight * scale) * slip;
    }
  }
  io.impulseOnField += impulseOnField;
  io.impulseOnShell -= impulseOnField;
  if (settings.enableRotation) {
    ++io.torqueEvaluations;
    io.angularImpulseOnField += handleField.cross(impulseOnField);
    io.angularImpulseOnShell -= handleShell.cross(impulseOnField);
  }
  io.maxPenetration = std::max(io.maxPenetration, -depth);
  return depth;
}

PenaltyPointPath makePenaltyPointPath(const Vec3& pointInShell, const Vec3& normalInShell,
                                      const PenaltyBodyMotion& shell, const PenaltyBodyMotion& fieldBody);

/// Sets the forces from the impulses (eq. 5). Throws sdfccd::Error if dt is not positive and finite.
void finishPenaltyResult(double timestep, PenaltyResult& io);

}  // namespace detail

/// Integrates the penalty impulses of one (shell body, field body) pair over a step of `timestep` seconds.
/// `pointsInShell` are the shell's points (the indices of `ccd.contacts` refer to them); each contact's
/// `pointNormalInShell` gives its normal. Continuous: uses each contact's intervals (run the CCD with
/// CcdMode::AllIntervals). Discrete: ignores the intervals and evaluates every listed contact at the end pose
/// (run the CCD with start = end so that it lists the points inside at the end). `Field` needs
/// `double distance(const Vec3& pointInSdf) const` (and `Vec3 gradient(const Vec3&) const` for
/// PenaltyDirection::FieldGradient). Throws sdfccd::Error on a bad timestep or point index.
template <class Field>
PenaltyResult integratePenalty(const std::vector<Vec3>& pointsInShell, const Field& field, const RigidCcdResult& ccd,
                               const PenaltyBodyMotion& shell, const PenaltyBodyMotion& fieldBody, double timestep,
                               const PenaltySettings& settings);

void checkPenaltyInput(std::size_t pointCount, const RigidCcdResult& ccd, double timestep,
                       const PenaltySettings& settings);

template <class Field>
PenaltyResult integratePenalty(const std::vector<Vec3>& pointsInShell, const Field& field, const RigidCcdResult& ccd,
                               const PenaltyBodyMotion& shell, const PenaltyBodyMotion& fieldBody, double timestep,
                               const PenaltySettings& settings) {
  checkPenaltyInput(pointsInShell.size(), ccd, timestep, settings);
  PenaltyResult result;
  const bool useDamping = settings.enableDamping && settings.damping > 0.0;
  const bool useFriction = settings.enableFriction && settings.friction > 0.0;
  const int pieces = std::max(1, settings.subintervals);
  for (const PointContact& contact : ccd.contacts) {
    const detail::PenaltyPointPath path = detail::makePenaltyPointPath(
        pointsInShell[static_cast<std::size_t>(contact.point)], contact.pointNormalInShell, shell, fieldBody);
    bool pushed = false;
    if (settings.model == PenaltyModel::Discrete) {
      pushed = detail::addPenaltySample(field, path, shell, fieldBody, 1.0, timestep, settings, useDamping, useFriction,
                                        result) < 0.0;
    } else {
      for (std::size_t i = 0; i < contact.intervals.size(); ++i) {
        const Interval& interval = contact.intervals[i];
        const double width = (interval.end - interval.begin) / pieces;
        if (!(width > 0.0)) continue;  // a touching instant carries no impulse
        for (int j = 0; j < pieces; ++j) {
          const double t = interval.begin + (j + 0.5) * width;
          if (detail::addPenaltySample(field, path, shell, fieldBody, t, width * timestep, settings, useDamping,
                                       useFriction, result) < 0.0) {
            pushed = true;
          }
        }
      }
    }
    if (pushed) ++result.contactCount;
  }
  detail::finishPenaltyResult(timestep, result);
  return result;
}

}  // namespace sdfccd
