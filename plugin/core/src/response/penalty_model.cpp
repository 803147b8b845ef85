/// @file
/// @brief The penalty model (Section 4.1, eqs. 3-5; see penalty_model.h), instantiated for every field type of
/// field_interface.h.
#include "sdfccd/response/penalty_model.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"

namespace sdfccd {

void checkPenaltyInput(std::size_t pointCount, const RigidCcdResult& ccd, double timestep,
                       const PenaltySettings& settings) {
  if (!(timestep > 0.0) || !std::isfinite(timestep)) {
    throw Error("penalty model: the timestep must be positive and finite (got " + std::to_string(timestep) + ")");
  }
  if (!(settings.stiffness >= 0.0) || !std::isfinite(settings.stiffness) || !(settings.damping >= 0.0) ||
      !std::isfinite(settings.damping)) {
    throw Error("penalty model: stiffness and damping must be finite and non-negative");
  }
  if (settings.subintervals < 1) throw Error("penalty model: subintervals must be at least 1");
  if (!(settings.friction >= 0.0) || !std::isfinite(settings.friction) || !(settings.frictionSlipSpeed > 0.0) ||
      !std::isfinite(settings.frictionSlipSpeed)) {
    throw Error("penalty model: friction must be finite and >= 0, frictionSlipSpeed positive");
  }
  for (const PointContact& contact : ccd.contacts) {
    if (contact.point < 0 || static_cast<std::size_t>(contact.point) >= pointCount) {
      throw Error("penalty model: contact point index " + std::to_string(contact.point) + " is out of range");
    }
  }
}

namespace {

/// Precomputed, per contact: the point's trajectory and what interpolates linearly in t.
struct PenaltyPointPath {
  Vec3 pointInSdfStart, pointInSdfEnd;        // field frame
  Vec3 normalInWorldStart, normalInWorldEnd;  // shell's outward normal
  Vec3 handleShellStart, handleShellEnd;      // world, from the shell body's COM to the point
  Vec3 handleFieldStart, handleFieldEnd;      // world, from the field body's COM to the point
  Mat3 worldFromSdfStart, worldFromSdfEnd;    // rotation of the field's frame (FieldGradient direction)
};

Vec3 lerp(const Vec3& a, const Vec3& b, double t) {
  return a + t * (b - a);
}

PenaltyPointPath makePenaltyPointPath(const Vec3& pointInShell, const Vec3& normalInShell, const ShellMotion& shell,
                                      const FieldMotion& fieldBody) {
  PenaltyPointPath path;
  const Vec3 pointInWorldStart = shell.worldFromShellStart * pointInShell;
  const Vec3 pointInWorldEnd = shell.worldFromShellEnd * pointInShell;
  path.pointInSdfStart = fieldBody.worldFromSdfStart.inverse() * pointInWorldStart;
  path.pointInSdfEnd = fieldBody.worldFromSdfEnd.inverse() * pointInWorldEnd;
  path.normalInWorldStart = shell.worldFromShellStart.linear() * normalInShell;
  path.normalInWorldEnd = shell.worldFromShellEnd.linear() * normalInShell;
  path.handleShellStart = pointInWorldStart - shell.worldFromShellStart * shell.centerOfMassInShell;
  path.handleShellEnd = pointInWorldEnd - shell.worldFromShellEnd * shell.centerOfMassInShell;
  path.handleFieldStart = pointInWorldStart - fieldBody.worldFromSdfStart * fieldBody.centerOfMassInSdf;
  path.handleFieldEnd = pointInWorldEnd - fieldBody.worldFromSdfEnd * fieldBody.centerOfMassInSdf;
  path.worldFromSdfStart = fieldBody.worldFromSdfStart.linear();
  path.worldFromSdfEnd = fieldBody.worldFromSdfEnd.linear();
  return path;
}

/// Adds the force at fraction t, weighted by `weight` seconds, to `io`. Returns the depth d (model units).
template <class Field>
double addPenaltySample(const Field& field, const PenaltyPointPath& path, const ShellMotion& shell,
                        const FieldMotion& fieldBody, double t, double weight, const PenaltySettings& settings,
                        bool useDamping, bool useFriction, PenaltyResult& io) {
  const double depth = field.distance(lerp(path.pointInSdfStart, path.pointInSdfEnd, t)) - settings.sigma;
  if (!(depth < 0.0)) return depth;
  Vec3 normal = lerp(path.normalInWorldStart, path.normalInWorldEnd, t);
  if (settings.direction == PenaltyDirection::FieldGradient) {
    const Vec3 gradientInSdf = field.gradient(lerp(path.pointInSdfStart, path.pointInSdfEnd, t));
    const Vec3 away = -lerp(path.worldFromSdfStart * gradientInSdf, path.worldFromSdfEnd * gradientInSdf, t);
    if (away.allFinite() && away.norm() > 0.0) normal = away;  // else: the shell normal (a flat spot of phi)
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
    const BodyVelocities& s = shell.velocity;
    const BodyVelocities& f = fieldBody.velocity;
    const Vec3 velocityShell =
        lerp(s.linearStart, s.linearEnd, t) + lerp(s.angularStart, s.angularEnd, t).cross(handleShell);
    const Vec3 velocityField =
        lerp(f.linearStart, f.linearEnd, t) + lerp(f.angularStart, f.angularEnd, t).cross(handleField);
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

/// Sets the forces from the impulses (eq. 5).
void finishPenaltyResult(double timestep, PenaltyResult& io) {
  const double inverse = 1.0 / timestep;
  io.forceOnShell = io.impulseOnShell * inverse;
  io.torqueOnShell = io.angularImpulseOnShell * inverse;
  io.forceOnField = io.impulseOnField * inverse;
  io.torqueOnField = io.angularImpulseOnField * inverse;
}

}  // namespace

template <class Field>
PenaltyResult integratePenalty(const std::vector<Vec3>& pointsInShell, const Field& field, const RigidCcdResult& ccd,
                               const ShellMotion& shell, const FieldMotion& fieldBody, double timestep,
                               const PenaltySettings& settings) {
  checkPenaltyInput(pointsInShell.size(), ccd, timestep, settings);
  PenaltyResult result;
  const bool useDamping = settings.enableDamping && settings.damping > 0.0;
  const bool useFriction = settings.enableFriction && settings.friction > 0.0;
  const int pieces = std::max(1, settings.subintervals);
  for (const PointContact& contact : ccd.contacts) {
    const PenaltyPointPath path = makePenaltyPointPath(pointsInShell[static_cast<std::size_t>(contact.point)],
                                                       contact.pointNormalInShell, shell, fieldBody);
    bool pushed = false;
    if (settings.model == PenaltyModel::Discrete) {
      pushed = addPenaltySample(field, path, shell, fieldBody, 1.0, timestep, settings, useDamping, useFriction,
                                result) < 0.0;
    } else {
      for (std::size_t i = 0; i < contact.intervals.size(); ++i) {
        const Interval& interval = contact.intervals[i];
        const double width = (interval.end - interval.begin) / pieces;
        if (!(width > 0.0)) continue;  // a touching instant carries no impulse
        for (int j = 0; j < pieces; ++j) {
          const double t = interval.begin + (j + 0.5) * width;
          if (addPenaltySample(field, path, shell, fieldBody, t, width * timestep, settings, useDamping, useFriction,
                               result) < 0.0) {
            pushed = true;
          }
        }
      }
    }
    if (pushed) ++result.contactCount;
  }
  finishPenaltyResult(timestep, result);
  return result;
}

#define SDFCCD_INSTANTIATE_PENALTY(Field)                                                                       \
  template PenaltyResult integratePenalty<Field>(const std::vector<Vec3>&, const Field&, const RigidCcdResult&, \
                                                 const ShellMotion&, const FieldMotion&, double,                \
                                                 const PenaltySettings&);
SDFCCD_FOR_EACH_FIELD(SDFCCD_INSTANTIATE_PENALTY)
#undef SDFCCD_INSTANTIATE_PENALTY

}  // namespace sdfccd
