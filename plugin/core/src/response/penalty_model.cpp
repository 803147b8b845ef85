/// @file
/// @brief The penalty model (Section 4.1, eqs. 3-5; see penalty_model.h), instantiated for every field type of
/// field_interface.h; beyond the paper: per-area stiffness with per-pair caps, the Blend direction and anchor
/// friction (docs/design/contact-response.md, penalty mode).
#include "sdfccd/response/penalty_model.h"
#include "sdfccd/response/contact_normal.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "response/penalty_vector_ops.h"
#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/field/polytope_fields.h"

namespace sdfccd {

namespace {

/// checkPenaltyInput's messages: the checks one by one, throwing at the first that fails. Out of line and cold:
/// the hot path (every role of every step) tests the same conditions at once.
[[gnu::cold, gnu::noinline]] void throwBadPenaltyInput(double timestep, const PenaltySettings& settings) {
  if (!(timestep > 0.0) || !std::isfinite(timestep)) {
    throw Error("penalty model: the timestep must be positive and finite (got " + std::to_string(timestep) + ")");
  }
  if (!(settings.stiffness >= 0.0) || !std::isfinite(settings.stiffness) || !(settings.damping >= 0.0) ||
      !std::isfinite(settings.damping)) {
    throw Error("penalty model: stiffness and damping must be finite and non-negative");
  }
  if (!(settings.stiffnessPerArea >= 0.0) || !std::isfinite(settings.stiffnessPerArea)) {
    throw Error("penalty model: stiffnessPerArea must be finite and non-negative");
  }
  if (!(settings.dampingRatio <= 2.0) || !std::isfinite(settings.dampingRatio)) {
    throw Error("penalty model: dampingRatio must be at most 2 (negative: per-point damping)");
  }
  if (!(settings.roleScale > 0.0) || !(settings.roleScale <= 1.0)) {
    throw Error("penalty model: roleScale must be in (0, 1]");
  }
  if (!(settings.blendStartCells >= 0.0) || !(settings.blendEndCells > settings.blendStartCells) ||
      !std::isfinite(settings.blendEndCells)) {
    throw Error("penalty model: blend cells must satisfy 0 <= blendStartCells < blendEndCells, finite");
  }
  if (settings.subintervals < 1) throw Error("penalty model: subintervals must be at least 1");
  if (!(settings.friction >= 0.0) || !std::isfinite(settings.friction) || !(settings.frictionSlipSpeed > 0.0) ||
      !std::isfinite(settings.frictionSlipSpeed)) {
    throw Error("penalty model: friction must be finite and >= 0, frictionSlipSpeed positive");
  }
}

[[gnu::cold, gnu::noinline]] void throwBadContactPoint(int point) {
  throw Error("penalty model: contact point index " + std::to_string(point) + " is out of range");
}

/// lo <= x <= hi (false for NaN).
bool within(double x, double lo, double hi) {
  return x >= lo && x <= hi;
}

}  // namespace

void checkPenaltyInput(std::size_t pointCount, const RigidCcdResult& ccd, double timestep,
                       const PenaltySettings& settings) {
  // throwBadPenaltyInput's conditions at once: a positive or non-negative finite value is one in (0, max] or
  // [0, max] (NaN fails every comparison); dampingRatio <= 2 and finite is [-max, 2]; blendEndCells >
  // blendStartCells >= 0 leaves only its upper bound to check.
  constexpr double kMax = std::numeric_limits<double>::max();
  const bool valid = timestep > 0.0 && timestep <= kMax && within(settings.stiffness, 0.0, kMax) &&
                     within(settings.damping, 0.0, kMax) && within(settings.stiffnessPerArea, 0.0, kMax) &&
                     within(settings.dampingRatio, -kMax, 2.0) && settings.roleScale > 0.0 &&
                     settings.roleScale <= 1.0 && settings.blendStartCells >= 0.0 &&
                     settings.blendEndCells > settings.blendStartCells && settings.blendEndCells <= kMax &&
                     settings.subintervals >= 1 && within(settings.friction, 0.0, kMax) &&
                     settings.frictionSlipSpeed > 0.0 && settings.frictionSlipSpeed <= kMax;
  if (!valid) throwBadPenaltyInput(timestep, settings);  // names the failing check (always one)
  for (const PointContact& contact : ccd.contacts) {
    // A negative index converts to one above any point count.
    if (static_cast<std::size_t>(contact.point) >= pointCount) throwBadContactPoint(contact.point);
  }
}

namespace {

/// Tangential damping c_t = share * c_i (the anchor's design takes c_t = c_i: docs/design/contact-response.md,
/// static friction). The caps bound only the normal mode; with the full c_i the rocking mode of a resting box,
/// damped by the normal and the tangential dampers together (lever arms: half its width and its half height),
/// overshoots the explicit limit at zeta = 1 and 1 ms (a compound of two 10 cm boxes diverges with a period of 2
/// steps); half is stable and still holds the anchor.
constexpr double kTangentialDampingShare = 0.5;

// The sampling loop's vector arithmetic (penalty_vector_ops.h).
using detail::scalar_ops::addScaled;
using detail::scalar_ops::addTo;
using detail::scalar_ops::lerp;
using detail::scalar_ops::LinearMat3;
using detail::scalar_ops::LinearVec3;
using detail::scalar_ops::rotate;
using detail::scalar_ops::rotateBack;
using detail::scalar_ops::scaled;
using detail::scalar_ops::subtractFrom;
using detail::scalar_ops::subtractScaled;
using detail::scalar_ops::unit;

/// Is every component +0.0 (the bits of zero, not a -0)?
bool positiveZero(const Vec3& v) {
  const Vec3 zero = Vec3::Zero();
  return std::memcmp(v.data(), zero.data(), 3 * sizeof(double)) == 0;
}

/// Is x -0.0?
bool negativeZero(double x) {
  return x == 0.0 && std::signbit(x);
}

/// Does a + t (b - a) give a, bit for bit, for every t in [0, 1]? It does when b is a bit for bit, finite and
/// without -0: b - a is then +0, t (+0) is +0, and a + (+0) is a (only -0 + +0 would change: to +0).
template <class Matrix>
bool lerpStaysAt(const Matrix& a, const Matrix& b) {
  if (std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) != 0) return false;
  for (Eigen::Index k = 0; k < a.size(); ++k) {
    if (!std::isfinite(a.data()[k]) || negativeZero(a.data()[k])) return false;
  }
  return true;
}

/// What every contact's path of one role shares, computed once per role instead of once per contact (the same
/// expressions, so the paths are bit for bit what per-contact evaluation gives).
struct PenaltyPathFrames {
  Rigid sdfFromWorldStart, sdfFromWorldEnd;
  Vec3 shellComStart, shellComEnd;  // world
  Vec3 fieldComStart, fieldComEnd;  // world
  /// The field's rotation interpolates to its start value at every t in [0, 1] (lerpStaysAt: a static field, a
  /// field body that only translates): the anchors' stretch needs no interpolated matrix.
  bool fieldStill = false;
  /// Set (setConstantAway) when the direction away from the field, -grad phi / |grad phi| in world, is the same
  /// at every sample: a plane that does not turn. penaltyDirection then skips its product and normalization.
  bool constantAway = false;
  Vec3 awayUnit = Vec3::Zero();
  Mat3 worldFromSdfStart, worldFromSdfEnd;  // rotation of the field's frame (gradient, anchors)
  LinearMat3 worldFromSdf;                  // from worldFromSdfStart to worldFromSdfEnd
  bool fieldTurns = true;                   // worldFromSdfStart != worldFromSdfEnd

  PenaltyPathFrames(const ShellMotion& shell, const FieldMotion& fieldBody)
      : sdfFromWorldStart(fieldBody.worldFromSdfStart.inverse()),
        sdfFromWorldEnd(fieldBody.worldFromSdfEnd.inverse()),
        shellComStart(shell.worldFromShellStart * shell.centerOfMassInShell),
        shellComEnd(shell.worldFromShellEnd * shell.centerOfMassInShell),
        fieldComStart(fieldBody.worldFromSdfStart * fieldBody.centerOfMassInSdf),
        fieldComEnd(fieldBody.worldFromSdfEnd * fieldBody.centerOfMassInSdf),
        worldFromSdfStart(fieldBody.worldFromSdfStart.linear()),
        worldFromSdfEnd(fieldBody.worldFromSdfEnd.linear()),
        worldFromSdf(worldFromSdfStart, worldFromSdfEnd),
        fieldTurns(worldFromSdfStart != worldFromSdfEnd) {
    fieldStill = lerpStaysAt(worldFromSdfStart, worldFromSdfEnd);
  }
};

/// What every sample of one role shares besides the frames, taken once per role: the settings' switches, the blend
/// band (the same products as per sample), and the bodies' velocities as linear functions of t.
struct SampleRole {
  const PenaltyPathFrames& frames;
  double sigma = 0.0;
  bool useDamping = false;
  bool useFriction = false;
  bool anchorFriction = false;  // FrictionModel::Anchor with a table
  bool rotation = false;
  bool needVelocity = false;
  bool needHandles = false;
  bool gradientDirection = false;  // the direction is not the shell normal alone
  bool blendBand = false;          // PenaltyDirection::Blend with a cell size
  double blendStart = 0.0;         // d0 = blendStartCells * cellSize
  double blendWidth = 0.0;         // d1 - d0
  double friction = 0.0;
  double frictionSlipSpeed = 0.0;
  double dampingPerStiffness = 0.0;
  LinearVec3 shellLinear, shellAngular, fieldLinear, fieldAngular;  // world
  bool fieldAtRest = false;  // the field body's velocities are +0 throughout (bit for bit): a static body

  SampleRole(const PenaltyPathFrames& pathFrames, const ShellMotion& shell, const FieldMotion& fieldBody,
             const PenaltySettings& settings, const PenaltyRoleInput& input, bool damping, bool friction_)
      : frames(pathFrames),
        sigma(settings.sigma),
        useDamping(damping),
        useFriction(friction_),
        anchorFriction(settings.frictionModel == FrictionModel::Anchor && input.anchors != nullptr),
        rotation(settings.enableRotation),
        needVelocity(damping || friction_),
        needHandles(needVelocity || settings.enableRotation),
        gradientDirection(settings.direction != PenaltyDirection::ShellNormal),
        blendBand(settings.direction == PenaltyDirection::Blend && input.cellSize > 0.0),
        friction(settings.friction),
        frictionSlipSpeed(settings.frictionSlipSpeed),
        dampingPerStiffness(input.dampingPerStiffness),
        shellLinear(shell.velocity.linearStart, shell.velocity.linearEnd),
        shellAngular(shell.velocity.angularStart, shell.velocity.angularEnd),
        fieldLinear(fieldBody.velocity.linearStart, fieldBody.velocity.linearEnd),
        fieldAngular(fieldBody.velocity.angularStart, fieldBody.velocity.angularEnd) {
    const double d0 = settings.blendStartCells * input.cellSize;
    const double d1 = settings.blendEndCells * input.cellSize;
    blendStart = d0;
    blendWidth = d1 - d0;
    const BodyVelocities& v = fieldBody.velocity;
    fieldAtRest = positiveZero(v.linearStart) && positiveZero(v.linearEnd) && positiveZero(v.angularStart) &&
                  positiveZero(v.angularEnd);
  }
};

/// Precomputed, per contact: the point's trajectory and what interpolates linearly in t. Built in place (the
/// trajectory's members are not first zeroed: a fifth of the per-contact set-up).
struct PenaltyPointPath {
  Vec3 pointInSdfEnd;                 // field frame (kept: start + 1 (end - start) need not round back to it)
  LinearVec3 pointInSdf;              // from its start (pointInSdf.start) to pointInSdfEnd
  LinearVec3 normalInWorld;           // shell's outward normal
  LinearVec3 handleShell;             // world, from the shell body's COM to the point
  LinearVec3 handleField;             // world, from the field body's COM to the point
  Vec3 anchorInField = Vec3::Zero();  // the point's anchor (anchor friction), as matched this step
  double stiffness = 0.0;             // k_i, N/m
  double damping = 0.0;               // c_i, N s/m
  FrictionSettings law;               // anchor friction's tangential law for this point
  std::size_t anchor = 0;             // index in the anchor table (anchor friction)
  double shellWeight = 0.0;           // the least weight of the shell normal in the direction (contact_normal.h)

  PenaltyPointPath(const Vec3& pointInShell, const Vec3& normalInShell, const ShellMotion& shell,
                   const PenaltyPathFrames& frames)
      : PenaltyPointPath(shell.worldFromShellStart * pointInShell, shell.worldFromShellEnd * pointInShell,
                         normalInShell, shell, frames) {}

 private:
  PenaltyPointPath(const Vec3& pointInWorldStart, const Vec3& pointInWorldEnd, const Vec3& normalInShell,
                   const ShellMotion& shell, const PenaltyPathFrames& frames)
      : pointInSdfEnd(frames.sdfFromWorldEnd * pointInWorldEnd),
        pointInSdf(frames.sdfFromWorldStart * pointInWorldStart, pointInSdfEnd),
        normalInWorld(shell.worldFromShellStart.linear() * normalInShell,
                      shell.worldFromShellEnd.linear() * normalInShell),
        handleShell(pointInWorldStart - frames.shellComStart, pointInWorldEnd - frames.shellComEnd),
        handleField(pointInWorldStart - frames.fieldComStart, pointInWorldEnd - frames.fieldComEnd) {}
};

/// A plane's gradient is its normal everywhere: for a still field, penaltyDirection's away vector
/// -lerp(R n, R n, t) is -(R n) at every t (lerpStaysAt), normalized once here with the very operations it
/// applies per sample. Other fields, or a product with a -0 or non-finite component, keep the per-sample path.
template <class Field>
void setConstantAway(const Field& field, const FieldMotion& fieldBody, PenaltyPathFrames& frames) {
  if constexpr (std::is_same_v<Field, PlaneField>) {
    if (!frames.fieldStill) return;
    const Mat3 worldFromSdf = fieldBody.worldFromSdfStart.linear();
    const Vec3 awayStart = worldFromSdf * field.gradient(Vec3::Zero());
    if (!lerpStaysAt(awayStart, awayStart)) return;
    Vec3 away = -awayStart;
    const double awayLength = away.norm();
    if (!(away.allFinite() && awayLength > 0.0)) return;
    away /= awayLength;
    frames.awayUnit = away;
    frames.constantAway = true;
  } else {
    (void)field;
    (void)fieldBody;
    (void)frames;
  }
}

/// phi at `pointInSdf`; for a grid field inside its box also the gradient there (`outHasGradient`), from the same
/// cell lookup: GridField::distance and ::gradient interpolate that cell each, so the values are bit-identical
/// and a penalty sample pays one lookup instead of two.
template <class Field>
SDFCCD_FORCE_INLINE double distanceWithGradient(const Field& field, const Vec3& pointInSdf, Vec3& outGradient,
                                                bool& outHasGradient) {
  outHasGradient = false;
  if constexpr (std::is_same_v<Field, GridField>) {
    if (field.grid().contains(pointInSdf)) {
      outHasGradient = true;
      return field.grid().interpolate(pointInSdf, outGradient);
    }
  }
  return field.distance(pointInSdf);
}

/// The field at a contact's end position p_sdf(1) (PenaltyPointPath::pointInSdfEnd): phi and its gradient, as
/// field.distance and field.gradient give them there. perAreaCoefficients takes the gradient at that point and the
/// anchors' end-of-step update phi and the gradient (integratePenaltyWithCoefficients shares them).
struct EndLookup {
  double distance = 0.0;
  Vec3 gradient = Vec3::Zero();
};

/// phi and the gradient at `pointInSdf`: one cell lookup for a grid field inside its box (distanceWithGradient).
template <class Field>
EndLookup lookUpEnd(const Field& field, const Vec3& pointInSdf) {
  EndLookup out;
  bool hasGradient = false;
  out.distance = distanceWithGradient(field, pointInSdf, out.gradient, hasGradient);
  if (!hasGradient) out.gradient = field.gradient(pointInSdf);
  return out;
}

/// Bitwise equality (a -0 is not a +0): a value looked up at `b` then stands for one at `a`, whatever the field.
bool sameBits(const Vec3& a, const Vec3& b) {
  return std::memcmp(a.data(), b.data(), 3 * sizeof(double)) == 0;
}

/// The unit direction the field body is pushed at fraction t, depth d (< 0); zero when there is none.
/// `gradientAtT`: the field's gradient at the point at t when already known (else looked up).
template <class Field>
SDFCCD_FORCE_INLINE Vec3 penaltyDirection(const Field& field, const PenaltyPointPath& path, const SampleRole& role,
                                          double t, double depth, const Vec3* gradientAtT = nullptr) {
  const PenaltyPathFrames& frames = role.frames;
  const Vec3 shellNormal = path.normalInWorld.at(t);
  Vec3 normal = shellNormal;
  if (role.gradientDirection) {
    double w = 0.0;  // weight of the shell normal
    if (role.blendBand) {
      const double x = std::clamp((-depth - role.blendStart) / role.blendWidth, 0.0, 1.0);
      w = x * x * (3.0 - 2.0 * x);
    }
    w = std::max(w, path.shellWeight);
    if (w < 1.0) {
      Vec3 away;
      bool hasAway = true;
      if (frames.constantAway && t >= 0.0 && t <= 1.0) {
        away = frames.awayUnit;  // a still plane: what the lines below give, computed once (setConstantAway)
      } else {
        const Vec3 gradientInSdf = gradientAtT != nullptr ? *gradientAtT : field.gradient(path.pointInSdf.at(t));
        // A field body that does not turn during the step (a static one, always) has one product, not two.
        const Vec3 awayStart = rotate(frames.worldFromSdfStart, gradientInSdf);
        const Vec3 awayEnd = frames.fieldTurns ? rotate(frames.worldFromSdfEnd, gradientInSdf) : awayStart;
        const Vec3 towards = lerp(awayStart, awayEnd, t);
        away = Vec3(-towards.x(), -towards.y(), -towards.z());
        const double awayLength = away.norm();
        hasAway = finiteValues(away.data(), 3) && awayLength > 0.0;  // else: the shell normal (a flat spot of phi)
        if (hasAway) away = unit(away, awayLength);
      }
      if (hasAway) {
        // (1 - w) away + w shellNormal / |shellNormal| where |shellNormal| > 0 (norm() is the square root of
        // squaredNorm(), positive exactly when it is), else away.
        const double shellSquared = shellNormal.squaredNorm();
        Vec3 blended = away;
        if (shellSquared > 0.0) {
          if (w == 0.0 && finiteValues(shellNormal.data(), 3)) {
            // Shallow (most samples): 1 away_i is away_i, and 0 (s_i / |s|) is the zero of s_i's sign, 0 s_i (s_i
            // finite, |s| > 0: the quotient is finite), so the same bits without the norm and the divisions.
            blended = Vec3(away.x() + 0.0 * shellNormal.x(), away.y() + 0.0 * shellNormal.y(),
                           away.z() + 0.0 * shellNormal.z());
          } else {
            const double shellLength = std::sqrt(shellSquared);
            const double keep = 1.0 - w;
            blended = Vec3(keep * away.x() + w * (shellNormal.x() / shellLength),
                           keep * away.y() + w * (shellNormal.y() / shellLength),
                           keep * away.z() + w * (shellNormal.z() / shellLength));
          }
        }
        // The blend's length is the normalization's (the same norm of the same vector, taken once).
        const double blendedLength = blended.norm();
        if (blendedLength > 1e-6) return unit(blended, blendedLength);
        // else opposed directions: the shell normal
      }
    }
  }
  const double normalLength = normal.norm();
  if (!(normalLength > 0.0)) return Vec3::Zero();  // the normal turned half a turn during the step
  return unit(normal, normalLength);
}

/// The pair's damping as Rayleigh (stiffness-proportional) damping of its elastic wrench W (per-area law,
/// continuous model; docs/design/contact-response.md). The per-point dampers c_i v_n,i are stiffness-proportional
/// (c_i = beta k_i), so their force is beta times the rate of change of the elastic force; their torque,
/// h x (beta d/dt f), misses the part of beta d/dt (h x f) that comes from the handle h moving, beta (dh/dt x f)
/// (the lever term; dh_shell/dt = w_s x h_s for the shell's material point, dh_field/dt = v_point - v_com,field).
/// Without it a patch that travels through the shell is damped as if it deformed: on a rolling sphere the points
/// enter in front and leave behind and W stays constant, yet the dampers push harder on the approaching front
/// than on the receding back and brake the roll (to a = 0.69 of 5/7 g sin theta). With it the pair's
/// damping is beta dW/dt: it damps what changes the wrench (approach, bounce, rocking), not a steady roll. For
/// that sum to hold, a point's damper is not clamped at zero on its own (a receding point may pull) but the
/// pair's: damping never takes more than the pair's elastic impulse along its direction (finishPairDamping).
struct PairWrench {
  Vec3 forceOnField = Vec3::Zero();   // N s
  Vec3 torqueOnField = Vec3::Zero();  // N m s, about the field body's centre of mass
  Vec3 torqueOnShell = Vec3::Zero();  // N m s, about the shell body's centre of mass

  SDFCCD_FORCE_INLINE void add(const Vec3& onField, const Vec3& handleField, const Vec3& handleShell) {
    addTo(forceOnField, onField);
    addTo(torqueOnField, handleField.cross(onField));
    subtractFrom(torqueOnShell, handleShell.cross(onField));
  }
};

struct PairDamping {
  Vec3 elastic = Vec3::Zero();  // N s, the elastic impulse on the field body
  PairWrench damping;           // the damping impulses (dampers and lever term)
};

/// Damping never pulls the pair together: scales its damping down to cancel at most the elastic impulse.
void finishPairDamping(const PairDamping& pair, PenaltyResult& io) {
  const double elasticLength = pair.elastic.norm();
  if (!(elasticLength > 0.0)) return;
  const Vec3 direction = pair.elastic / elasticLength;
  const double damping = pair.damping.forceOnField.dot(direction);
  if (elasticLength + damping >= 0.0) return;
  const double remove = 1.0 - elasticLength / -damping;  // share of the damping taken back
  io.impulseOnField -= remove * pair.damping.forceOnField;
  io.impulseOnShell += remove * pair.damping.forceOnField;
  io.angularImpulseOnField -= remove * pair.damping.torqueOnField;
  io.angularImpulseOnShell -= remove * pair.damping.torqueOnShell;
}

/// Adds the force at fraction t, weighted by `weight` seconds, to `io`. With `pairDamping`, the damping is the
/// pair's Rayleigh damping (see PairDamping). Returns the depth d (model units).
template <class Field>
SDFCCD_FORCE_INLINE double addPenaltySample(const Field& field, const PenaltyPointPath& path, const SampleRole& role,
                                            double t, double weight, PenaltyResult& io,
                                            PairDamping* pairDamping = nullptr) {
  const Vec3 pointInSdf = path.pointInSdf.at(t);
  Vec3 gradient;
  bool hasGradient = false;
  const double depth = distanceWithGradient(field, pointInSdf, gradient, hasGradient) - role.sigma;
  if (!(depth < 0.0)) return depth;
  const Vec3 normal = penaltyDirection(field, path, role, t, depth, hasGradient ? &gradient : nullptr);
  if (normal.isZero(0.0)) return depth;
  ++io.samples;
  double magnitude = -path.stiffness * depth;  // N
  Vec3 handleShell = Vec3::Zero();
  Vec3 handleField = Vec3::Zero();
  if (role.needHandles) {
    handleShell = path.handleShell.at(t);
    handleField = path.handleField.at(t);
  }
  Vec3 relativeVelocity = Vec3::Zero();  // of the shell's point relative to the field body's material point
  Vec3 handleRateShell = Vec3::Zero();   // d/dt of the handles with the point's own motion (lever damping)
  Vec3 handleRateField = Vec3::Zero();
  if (role.needVelocity) {
    handleRateShell = role.shellAngular.at(t).cross(handleShell);
    const Vec3 shellLinear = role.shellLinear.at(t);
    const Vec3 velocityShell(shellLinear.x() + handleRateShell.x(), shellLinear.y() + handleRateShell.y(),
                             shellLinear.z() + handleRateShell.z());
    if (role.fieldAtRest && std::isfinite(t) && finiteValues(handleField.data(), 3)) {
      // A field body at rest (the ground): its velocity at t is +0 + t (+0) = +0 and its turn +0 x h a zero for
      // finite t and h, so its material point's velocity is +0 + (a zero) = +0, and v - (+0) is v, bit for bit.
      handleRateField = velocityShell;
      relativeVelocity = velocityShell;
    } else {
      const Vec3 fieldLinear = role.fieldLinear.at(t);
      const Vec3 fieldTurn = role.fieldAngular.at(t).cross(handleField);
      const Vec3 velocityField(fieldLinear.x() + fieldTurn.x(), fieldLinear.y() + fieldTurn.y(),
                               fieldLinear.z() + fieldTurn.z());
      handleRateField = Vec3(velocityShell.x() - fieldLinear.x(), velocityShell.y() - fieldLinear.y(),
                             velocityShell.z() - fieldLinear.z());
      relativeVelocity = Vec3(velocityShell.x() - velocityField.x(), velocityShell.y() - velocityField.y(),
                              velocityShell.z() - velocityField.z());
    }
  }
  double pushMagnitude = magnitude;  // the normal force of the impulse (N)
  if (role.useDamping) {
    ++io.dampingEvaluations;
    const double approachSpeed = relativeVelocity.dot(normal);  // m/s, > 0 approaching
    const double elastic = magnitude;
    magnitude = std::max(0.0, elastic + path.damping * approachSpeed);
    pushMagnitude = magnitude;
    if (pairDamping != nullptr) {
      // Rayleigh damping of the pair (addLeverDamping): the point's damper is not clamped here but with the
      // pair's total (finishPairDamping); `magnitude` (>= 0) still bounds the point's friction.
      pushMagnitude = elastic + path.damping * approachSpeed;
      const Vec3 dampingImpulse = scaled(weight * path.damping * approachSpeed, normal);
      addScaled(pairDamping->elastic, weight * elastic, normal);
      pairDamping->damping.add(dampingImpulse, handleField, handleShell);
      if (role.rotation) {
        const Vec3 betaElastic = scaled(role.dampingPerStiffness * weight * elastic, normal);
        const Vec3 leverField = handleRateField.cross(betaElastic);
        const Vec3 leverShell = handleRateShell.cross(betaElastic);
        addTo(pairDamping->damping.torqueOnField, leverField);
        subtractFrom(pairDamping->damping.torqueOnShell, leverShell);
        addTo(io.angularImpulseOnField, leverField);
        subtractFrom(io.angularImpulseOnShell, leverShell);
      }
    }
  }
  Vec3 impulseOnField = scaled(weight * pushMagnitude, normal);
  if (role.useFriction) {
    ++io.frictionEvaluations;
    if (role.anchorFriction) {
      // The stretch from the anchor, fixed in the field's frame, taken to world with the field's rotation at t.
      // A still field's rotation interpolates to its start value (lerpStaysAt): no matrix to interpolate.
      const PenaltyPathFrames& frames = role.frames;
      const Vec3 fromAnchor(pointInSdf.x() - path.anchorInField.x(), pointInSdf.y() - path.anchorInField.y(),
                            pointInSdf.z() - path.anchorInField.z());
      const Vec3 stretchInWorld = frames.fieldStill && t >= 0.0 && t <= 1.0
                                      ? rotate(frames.worldFromSdfStart, fromAnchor)
                                      : rotate(frames.worldFromSdf.at(t), fromAnchor);
      const TangentialForce f =
          tangentialForce(stretchInWorld, Vec3::Zero(), normal, relativeVelocity, magnitude, path.law);
      subtractScaled(impulseOnField, weight, f.force);  // f acts on the shell's point
    } else {
      // The field body drags the shell's point backwards: on the field, the force follows the slip.
      const Vec3 slip = detail::tangentialPart(relativeVelocity, normal);
      const double slipSpeed = slip.norm();
      if (slipSpeed > 0.0) {
        const double scale = role.friction * magnitude / std::max(slipSpeed, role.frictionSlipSpeed);
        addScaled(impulseOnField, weight * scale, slip);
      }
    }
  }
  addTo(io.impulseOnField, impulseOnField);
  subtractFrom(io.impulseOnShell, impulseOnField);
  if (role.rotation) {
    ++io.torqueEvaluations;
    addTo(io.angularImpulseOnField, handleField.cross(impulseOnField));
    subtractFrom(io.angularImpulseOnShell, handleShell.cross(impulseOnField));
  }
  io.maxPenetration = std::max(io.maxPenetration, -depth);
  return depth;
}

/// Sets the forces from the impulses (eq. 5).
void finishPenaltyResult(double timestep, PenaltyResult& io) {
  const double inverse = 1.0 / timestep;
  io.forceOnShell = io.impulseOnShell * inverse;
  io.torqueOnShell = io.angularImpulseOnShell * inverse;
  io.forceOnField = io.impulseOnField * inverse;
  io.torqueOnField = io.angularImpulseOnField * inverse;
}

/// perAreaCoefficients; with `endLookups`, also phi and the gradient at each contact's end position, in contact
/// order (filled whenever the contacts' gradients are taken: empty if it returned before).
template <class Field>
PairResponseCoefficients perAreaCoefficientsImpl(const std::vector<Vec3>& pointsInShell, const Field& field,
                                                 const RigidCcdResult& ccd, const ShellMotion& shell,
                                                 const FieldMotion& fieldBody, double timestep,
                                                 const PenaltySettings& settings, PenaltyRoleInput& io,
                                                 std::vector<EndLookup>* endLookups) {
  if (endLookups != nullptr) endLookups->clear();
  PairResponseCoefficients out;
  io.stiffnessPerArea = 0.0;
  io.dampingPerStiffness = -1.0;
  if (!(settings.stiffnessPerArea > 0.0) || io.areas == nullptr || ccd.contacts.empty()) return out;
  if (io.areas->size() != pointsInShell.size()) {
    throw Error("penalty model: stiffnessPerArea needs one area per shell point (the shell has none)");
  }
  const double roleStiffnessPerArea = settings.roleScale * settings.stiffnessPerArea;
  double roleStiffness = 0.0;
  Vec3 centroid = Vec3::Zero();
  Vec3 normalSum = Vec3::Zero();
  const Mat3 worldFromSdfEnd = fieldBody.worldFromSdfEnd.linear();
  const Rigid sdfFromWorldEnd = fieldBody.worldFromSdfEnd.inverse();
  // Sized once, filled by index: a push_back per contact would be an out-of-line call.
  if (endLookups != nullptr) endLookups->resize(ccd.contacts.size());
  for (std::size_t n = 0; n < ccd.contacts.size(); ++n) {
    const std::size_t i = static_cast<std::size_t>(ccd.contacts[n].point);
    const double k = roleStiffnessPerArea * (*io.areas)[i];
    const Vec3 pointInWorld = shell.worldFromShellEnd * pointsInShell[i];
    roleStiffness += k;
    centroid += k * pointInWorld;
    // The point is the path's pointInSdfEnd (PenaltyPointPath: the same expression), so a lookup kept here
    // serves the anchor's end-of-step update too.
    const Vec3 pointInSdf = sdfFromWorldEnd * pointInWorld;
    Vec3 gradientInSdf;
    if (endLookups != nullptr) {
      EndLookup& lookup = (*endLookups)[n];
      lookup = lookUpEnd(field, pointInSdf);
      gradientInSdf = lookup.gradient;
    } else {
      gradientInSdf = field.gradient(pointInSdf);
    }
    const Vec3 gradient = worldFromSdfEnd * gradientInSdf;
    if (gradient.allFinite()) normalSum += k * gradient;
  }
  if (!(roleStiffness > 0.0)) return out;
  centroid /= roleStiffness;
  Vec3 normal = normalSum.norm() > 0.0 ? Vec3(normalSum.normalized()) : Vec3::UnitY();
  const double inverseMass =
      inverseEffectiveMassTerm(shell.mass.inverseMass, shell.mass.inverseInertiaInWorld,
                               centroid - shell.worldFromShellEnd * shell.centerOfMassInShell, normal) +
      inverseEffectiveMassTerm(fieldBody.mass.inverseMass, fieldBody.mass.inverseInertiaInWorld,
                               centroid - fieldBody.worldFromSdfEnd * fieldBody.centerOfMassInSdf, normal);
  const double zeta = settings.dampingRatio >= 0.0 ? settings.dampingRatio : 0.0;
  out = pairResponseCoefficients(roleStiffness / settings.roleScale, inverseMass, zeta, timestep, settings.caps);
  io.stiffnessPerArea = roleStiffnessPerArea * out.stiffnessScale;
  io.dampingPerStiffness = settings.dampingRatio >= 0.0 ? out.dampingPerStiffness : -1.0;
  return out;
}

/// integratePenalty; `endLookups` (null, or one per contact: perAreaCoefficientsImpl's) spare the anchors' update
/// its lookups.
template <class Field>
PenaltyResult integratePenaltyImpl(const std::vector<Vec3>& pointsInShell, const Field& field,
                                   const RigidCcdResult& ccd, const ShellMotion& shell, const FieldMotion& fieldBody,
                                   double timestep, const PenaltySettings& settings, const PenaltyRoleInput& input,
                                   const EndLookup* endLookups) {
  checkPenaltyInput(pointsInShell.size(), ccd, timestep, settings);
  PenaltyResult result;
  const bool perArea = input.stiffnessPerArea > 0.0 && input.areas != nullptr;
  if (perArea && input.areas->size() != pointsInShell.size()) {
    throw Error("penalty model: the areas must have one entry per shell point");
  }
  const bool dampingPerStiffness = input.dampingPerStiffness >= 0.0;
  const bool useDamping =
      settings.enableDamping && (dampingPerStiffness ? input.dampingPerStiffness > 0.0 : settings.damping > 0.0);
  const bool useFriction = settings.enableFriction && settings.friction > 0.0;
  const bool anchored = useFriction && settings.frictionModel == FrictionModel::Anchor && input.anchors != nullptr;
  const bool discrete = settings.model == PenaltyModel::Discrete;
  // The per-area law's damping (dampingPerStiffness) is the pair's Rayleigh damping in the continuous model; the
  // paper's per-point damping and the discrete model keep per-point dampers clamped at zero.
  PairDamping pairDamping;
  PairDamping* rayleigh = useDamping && input.dampingPerStiffness > 0.0 && !discrete ? &pairDamping : nullptr;
  const int pieces = std::max(1, settings.subintervals);
  if (anchored) input.anchors->beginMatch();
  PenaltyPathFrames frames(shell, fieldBody);
  setConstantAway(field, fieldBody, frames);
  const SampleRole role(frames, shell, fieldBody, settings, input, useDamping, useFriction);
  for (std::size_t n = 0; n < ccd.contacts.size(); ++n) {
    const PointContact& contact = ccd.contacts[n];
    const std::size_t index = static_cast<std::size_t>(contact.point);
    PenaltyPointPath path(pointsInShell[index], contact.pointNormalInShell, shell, frames);
    path.stiffness = perArea ? input.stiffnessPerArea * (*input.areas)[index] : settings.stiffness;
    path.damping = dampingPerStiffness ? input.dampingPerStiffness * path.stiffness : settings.damping;
    path.law.friction = settings.friction;
    path.law.tangentialStiffness = path.stiffness;
    path.law.tangentialDamping = kTangentialDampingShare * path.damping;
    if (input.curvatures != nullptr && role.gradientDirection) {
      // Where the point first touches (its start when it starts inside), which surface gives the direction.
      const Vec3 at = contact.state == SegmentState::StartsInside
                          ? path.pointInSdf.start
                          : path.pointInSdf.at(std::clamp(contact.fraction, 0.0, 1.0));
      const Vec3 gradient = field.gradient(at);
      const double length = gradient.norm();
      if (length > 0.0 && gradient.allFinite()) {
        const Vec3 shellNormalInSdf = frames.sdfFromWorldStart.linear() * path.normalInWorld.start;
        path.shellWeight = shellNormalWeightAt(field, at, Vec3(gradient / length), shellNormalInSdf,
                                               (*input.curvatures)[index], input.cellSize);
      }
    }
    if (anchored) {
      // A new point is anchored where it entered: p_sdf(t_hit), p_sdf(0) if it starts inside, the end pose in
      // the discrete model (its only sample).
      const Vec3 entry = discrete ? path.pointInSdfEnd
                         : contact.state == SegmentState::StartsInside
                             ? path.pointInSdf.start
                             : path.pointInSdf.at(std::clamp(contact.fraction, 0.0, 1.0));
      path.anchor = input.anchors->matchNext(contact.point, entry);
      path.anchorInField = input.anchors->anchors()[path.anchor].anchorInField;
    }
    bool pushed = false;
    if (discrete) {
      pushed = addPenaltySample(field, path, role, 1.0, timestep, result) < 0.0;
    } else {
      for (std::size_t i = 0; i < contact.intervals.size(); ++i) {
        const Interval& interval = contact.intervals[i];
        const double width = (interval.end - interval.begin) / pieces;
        if (!(width > 0.0)) continue;  // a touching instant carries no impulse
        for (int j = 0; j < pieces; ++j) {
          const double t = interval.begin + (j + 0.5) * width;
          if (addPenaltySample(field, path, role, t, width * timestep, result, rayleigh) < 0.0) {
            pushed = true;
          }
        }
      }
    }
    if (pushed) ++result.contactCount;
    if (anchored) {
      // End of the step: the anchor slips if the spring's normal force at the end cannot hold its stretch.
      // phi at the end position and, for the direction, the gradient at lerp(start, end, 1): the same point
      // unless rounding moved it (then looked up there), one lookup for both (or none: perAreaCoefficients').
      EndLookup end;
      bool hasGradient = true;
      if (endLookups != nullptr) {
        end = endLookups[n];
      } else {
        end.distance = distanceWithGradient(field, path.pointInSdfEnd, end.gradient, hasGradient);
      }
      const double depth = end.distance - settings.sigma;
      Vec3 normalInWorld = Vec3::Zero();
      if (depth < 0.0) {
        const bool atEnd = hasGradient && sameBits(path.pointInSdf.at(1.0), path.pointInSdfEnd);
        normalInWorld = penaltyDirection(field, path, role, 1.0, depth, atEnd ? &end.gradient : nullptr);
      }
      const double normalForce = depth < 0.0 ? -path.stiffness * depth : 0.0;
      const Vec3 normalInSdf = rotateBack(frames.worldFromSdfEnd, normalInWorld);
      if (input.anchors->updateAnchor(path.anchor, path.pointInSdfEnd, normalInSdf, normalForce, path.law) ==
          FrictionState::Slip) {
        ++result.slippingPoints;
      }
    }
  }
  if (anchored) input.anchors->endMatch();
  if (rayleigh != nullptr) finishPairDamping(pairDamping, result);
  finishPenaltyResult(timestep, result);
  return result;
}

}  // namespace

template <class Field>
PairResponseCoefficients perAreaCoefficients(const std::vector<Vec3>& pointsInShell, const Field& field,
                                             const RigidCcdResult& ccd, const ShellMotion& shell,
                                             const FieldMotion& fieldBody, double timestep,
                                             const PenaltySettings& settings, PenaltyRoleInput& io) {
  return perAreaCoefficientsImpl(pointsInShell, field, ccd, shell, fieldBody, timestep, settings, io, nullptr);
}

template <class Field>
PenaltyResult integratePenalty(const std::vector<Vec3>& pointsInShell, const Field& field, const RigidCcdResult& ccd,
                               const ShellMotion& shell, const FieldMotion& fieldBody, double timestep,
                               const PenaltySettings& settings, const PenaltyRoleInput& input) {
  return integratePenaltyImpl(pointsInShell, field, ccd, shell, fieldBody, timestep, settings, input, nullptr);
}

template <class Field>
PenaltyResult integratePenaltyWithCoefficients(const std::vector<Vec3>& pointsInShell, const Field& field,
                                               const RigidCcdResult& ccd, const ShellMotion& shell,
                                               const FieldMotion& fieldBody, double timestep,
                                               const PenaltySettings& settings, PenaltyRoleInput& io,
                                               PairResponseCoefficients& outCoefficients) {
  // The lookups are kept only when the anchors' update will read them (integratePenaltyImpl's `anchored`).
  const bool anchored = settings.enableFriction && settings.friction > 0.0 &&
                        settings.frictionModel == FrictionModel::Anchor && io.anchors != nullptr;
  thread_local std::vector<EndLookup> endLookups;
  outCoefficients = perAreaCoefficientsImpl(pointsInShell, field, ccd, shell, fieldBody, timestep, settings, io,
                                            anchored ? &endLookups : nullptr);
  const bool shared = anchored && endLookups.size() == ccd.contacts.size() && !ccd.contacts.empty();
  return integratePenaltyImpl(pointsInShell, field, ccd, shell, fieldBody, timestep, settings, io,
                              shared ? endLookups.data() : nullptr);
}

template <class Field>
PenaltyResult integratePenalty(const std::vector<Vec3>& pointsInShell, const Field& field, const RigidCcdResult& ccd,
                               const ShellMotion& shell, const FieldMotion& fieldBody, double timestep,
                               const PenaltySettings& settings) {
  return integratePenalty(pointsInShell, field, ccd, shell, fieldBody, timestep, settings, PenaltyRoleInput{});
}

#define SDFCCD_INSTANTIATE_PENALTY(Field)                                                                            \
  template PenaltyResult integratePenalty<Field>(const std::vector<Vec3>&, const Field&, const RigidCcdResult&,      \
                                                 const ShellMotion&, const FieldMotion&, double,                     \
                                                 const PenaltySettings&);                                            \
  template PenaltyResult integratePenalty<Field>(const std::vector<Vec3>&, const Field&, const RigidCcdResult&,      \
                                                 const ShellMotion&, const FieldMotion&, double,                     \
                                                 const PenaltySettings&, const PenaltyRoleInput&);                   \
  template PairResponseCoefficients perAreaCoefficients<Field>(                                                      \
      const std::vector<Vec3>&, const Field&, const RigidCcdResult&, const ShellMotion&, const FieldMotion&, double, \
      const PenaltySettings&, PenaltyRoleInput&);                                                                    \
  template PenaltyResult integratePenaltyWithCoefficients<Field>(                                                    \
      const std::vector<Vec3>&, const Field&, const RigidCcdResult&, const ShellMotion&, const FieldMotion&, double, \
      const PenaltySettings&, PenaltyRoleInput&, PairResponseCoefficients&);
SDFCCD_FOR_EACH_FIELD(SDFCCD_INSTANTIATE_PENALTY)
SDFCCD_FOR_EACH_TRIANGLE_FIELD(SDFCCD_INSTANTIATE_PENALTY)
#undef SDFCCD_INSTANTIATE_PENALTY

}  // namespace sdfccd
