/// @file
/// @brief The time-of-impact clamp's policy and impact (see time_of_impact_clamp.h).
#include "sdfccd/response/time_of_impact_clamp.h"

#include <algorithm>

namespace sdfccd {

ClampAction clampAction(bool deepEntry, bool shellKinematic, bool fieldKinematic) {
  if (!deepEntry) return ClampAction::None;
  return (shellKinematic || fieldKinematic) ? ClampAction::KinematicPush : ClampAction::Rewind;
}

namespace {

double denominatorTerm(const ImpactBody& b, const Vec3& point, const Vec3& normal) {
  if (!(b.inverseMass > 0.0)) return 0.0;
  const Vec3 axis = (point - b.centerOfMass).cross(normal);
  return b.inverseMass + axis.dot(b.inverseInertiaInWorld * axis);
}

void applyImpulse(ImpactBody& b, const Vec3& point, const Vec3& impulse) {
  if (!(b.inverseMass > 0.0)) return;
  b.linearVelocity += b.inverseMass * impulse;
  b.angularVelocity += b.inverseInertiaInWorld * (point - b.centerOfMass).cross(impulse);
}

}  // namespace

ImpactResult resolveImpact(const std::vector<ImpactPoint>& points, ImpactBody& shell, ImpactBody& field,
                           double restitution, int iterations) {
  ImpactResult result;
  std::vector<double> accumulated(points.size(), 0.0);
  // Each point leaves at e times the speed it approached with before the impact (0: it stops).
  std::vector<double> leaving(points.size(), 0.0);
  if (restitution > 0.0) {
    for (std::size_t k = 0; k < points.size(); ++k) {
      const Vec3& point = points[k].pointInWorld;
      const double approach = (shell.pointVelocity(point) - field.pointVelocity(point)).dot(points[k].normalInWorld);
      leaving[k] = restitution * std::max(0.0, -approach);
    }
  }
  for (int sweep = 0; sweep < iterations; ++sweep) {
    for (std::size_t k = 0; k < points.size(); ++k) {
      const Vec3& point = points[k].pointInWorld;
      const Vec3& normal = points[k].normalInWorld;
      const double denominator = denominatorTerm(shell, point, normal) + denominatorTerm(field, point, normal);
      if (!(denominator > 0.0)) continue;
      const double approach = (shell.pointVelocity(point) - field.pointVelocity(point)).dot(normal) - leaving[k];
      const double next = std::max(0.0, accumulated[k] - approach / denominator);
      const Vec3 impulse = normal * (next - accumulated[k]);
      accumulated[k] = next;
      applyImpulse(shell, point, impulse);
      applyImpulse(field, point, -impulse);
      result.impulseOnShell += impulse;
    }
  }
  for (double a : accumulated) {
    if (a > 0.0) ++result.activePoints;
  }
  return result;
}

Vec3 kinematicPushDistance(const Vec3& kinematicVelocity, const Vec3& normalInWorld, double hitFraction,
                           double timeStep) {
  const double advance = (1.0 - std::clamp(hitFraction, 0.0, 1.0)) * timeStep * kinematicVelocity.dot(normalInWorld);
  return advance > 0.0 ? Vec3(advance * normalInWorld) : Vec3::Zero();
}

}  // namespace sdfccd
