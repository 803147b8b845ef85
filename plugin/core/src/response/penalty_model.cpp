/// @file
/// @brief The non-template parts of the penalty model (Section 4.1; see penalty_model.h).
#include "sdfccd/response/penalty_model.h"

#include <cmath>
#include <string>

#include "sdfccd/error.h"

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

namespace detail {

PenaltyPointPath makePenaltyPointPath(const Vec3& pointInShell, const Vec3& normalInShell,
                                      const PenaltyBodyMotion& shell, const PenaltyBodyMotion& fieldBody) {
  PenaltyPointPath path;
  const Vec3 pointInWorldStart = shell.worldFromBodyStart * pointInShell;
  const Vec3 pointInWorldEnd = shell.worldFromBodyEnd * pointInShell;
  path.pointInSdfStart = fieldBody.worldFromBodyStart.inverse() * pointInWorldStart;
  path.pointInSdfEnd = fieldBody.worldFromBodyEnd.inverse() * pointInWorldEnd;
  path.normalInWorldStart = shell.worldFromBodyStart.linear() * normalInShell;
  path.normalInWorldEnd = shell.worldFromBodyEnd.linear() * normalInShell;
  path.handleShellStart = pointInWorldStart - shell.worldFromBodyStart * shell.centerOfMassInBody;
  path.handleShellEnd = pointInWorldEnd - shell.worldFromBodyEnd * shell.centerOfMassInBody;
  path.handleFieldStart = pointInWorldStart - fieldBody.worldFromBodyStart * fieldBody.centerOfMassInBody;
  path.handleFieldEnd = pointInWorldEnd - fieldBody.worldFromBodyEnd * fieldBody.centerOfMassInBody;
  path.worldFromSdfStart = fieldBody.worldFromBodyStart.linear();
  path.worldFromSdfEnd = fieldBody.worldFromBodyEnd.linear();
  return path;
}

void finishPenaltyResult(double timestep, PenaltyResult& io) {
  const double inverse = 1.0 / timestep;
  io.forceOnShell = io.impulseOnShell * inverse;
  io.torqueOnShell = io.angularImpulseOnShell * inverse;
  io.forceOnField = io.impulseOnField * inverse;
  io.torqueOnField = io.angularImpulseOnField * inverse;
}

}  // namespace detail
}  // namespace sdfccd
