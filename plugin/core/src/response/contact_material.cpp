/// @file
/// @brief Damping ratio from restitution, Bullet's material combine rules and the per-pair stability caps (see
/// contact_material.h).
#include "sdfccd/response/contact_material.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

void requireRange(double value, double lo, double hi, const char* name) {
  if (!(value >= lo && value <= hi)) {
    throw Error(std::string("contact material: ") + name + " must be in [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "]");
  }
}

void requirePositive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw Error(std::string("contact material: ") + name + " must be positive and finite");
  }
}

void requireNonNegative(double value, const char* name) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    throw Error(std::string("contact material: ") + name + " must be non-negative and finite");
  }
}

}  // namespace

double dampingRatioFromRestitution(double restitution) {
  requireRange(restitution, 0.0, 1.0, "restitution");
  if (restitution == 0.0) return 1.0;  // the limit e -> 0 of the formula, stated: critical damping
  const double lnE = std::log(restitution);
  return -lnE / std::sqrt(kPi * kPi + lnE * lnE);
}

double restitutionFromDampingRatio(double dampingRatio) {
  requireNonNegative(dampingRatio, "dampingRatio");
  if (dampingRatio >= 1.0) return 0.0;
  return std::exp(-dampingRatio * kPi / std::sqrt(1.0 - dampingRatio * dampingRatio));
}

double combineFriction(double frictionA, double frictionB) {
  requireNonNegative(frictionA, "friction");
  requireNonNegative(frictionB, "friction");
  return std::min(frictionA * frictionB, kMaxCombinedFriction);
}

double combineRestitution(double restitutionA, double restitutionB) {
  requireNonNegative(restitutionA, "restitution");
  requireNonNegative(restitutionB, "restitution");
  return restitutionA * restitutionB;
}

double inverseEffectiveMassTerm(double inverseMass, const Mat3& inverseInertiaInWorld, const Vec3& leverArmInWorld,
                                const Vec3& normalInWorld) {
  requireNonNegative(inverseMass, "inverseMass");
  const Vec3 axis = leverArmInWorld.cross(normalInWorld);
  const double term = inverseMass + axis.dot(inverseInertiaInWorld * axis);
  requireNonNegative(term, "inverse effective mass (inverse inertia not positive semi-definite or not finite)");
  return term;
}

void StabilityCapSettings::validate() const {
  requirePositive(maxOmegaDt, "maxOmegaDt");
  if (!(maxDampingDt > 0.0 && maxDampingDt < 2.0)) throw Error("contact material: maxDampingDt must be in (0, 2)");
}

double maxPairStiffness(double inverseEffectiveMass, double timeStep, double maxOmegaDt) {
  requirePositive(inverseEffectiveMass, "inverseEffectiveMass");
  requirePositive(timeStep, "timeStep");
  requirePositive(maxOmegaDt, "maxOmegaDt");
  const double omega = maxOmegaDt / timeStep;
  return omega * omega / inverseEffectiveMass;
}

double maxPairDamping(double inverseEffectiveMass, double timeStep, double maxDampingDt) {
  requirePositive(inverseEffectiveMass, "inverseEffectiveMass");
  requirePositive(timeStep, "timeStep");
  requirePositive(maxDampingDt, "maxDampingDt");
  return maxDampingDt / (inverseEffectiveMass * timeStep);
}

PairResponseCoefficients pairResponseCoefficients(double totalStiffness, double inverseEffectiveMass,
                                                  double dampingRatio, double timeStep,
                                                  const StabilityCapSettings& settings) {
  settings.validate();
  requireNonNegative(totalStiffness, "totalStiffness");
  requireNonNegative(inverseEffectiveMass, "inverseEffectiveMass");
  requireRange(dampingRatio, 0.0, 2.0, "dampingRatio");
  requirePositive(timeStep, "timeStep");
  PairResponseCoefficients out;
  out.totalStiffness = totalStiffness;
  // No dynamic body (infinite mass) or no stiffness: nothing moves, nothing to cap or damp.
  if (inverseEffectiveMass == 0.0 || totalStiffness == 0.0) return out;
  const double omegaDt = std::sqrt(totalStiffness * inverseEffectiveMass) * timeStep;
  if (omegaDt > settings.maxOmegaDt) {
    const double ratio = settings.maxOmegaDt / omegaDt;
    out.stiffnessScale = ratio * ratio;
    out.stiffnessCapped = true;
  }
  out.totalStiffness = totalStiffness * out.stiffnessScale;
  const double omega = std::sqrt(out.totalStiffness * inverseEffectiveMass);  // 1/s, after the cap
  out.totalDamping = 2.0 * dampingRatio * out.totalStiffness / omega;         // = 2 zeta sqrt(K m_eff)
  const double dampingDt = out.totalDamping * timeStep * inverseEffectiveMass;
  if (dampingDt > settings.maxDampingDt) {
    out.totalDamping *= settings.maxDampingDt / dampingDt;
    out.dampingCapped = true;
  }
  out.dampingPerStiffness = out.totalDamping / out.totalStiffness;
  return out;
}

}  // namespace sdfccd
