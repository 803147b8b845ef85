/// @file
/// @brief Contact material and per-pair stability caps for the penalty response (docs/design/contact-response.md,
/// damping and stability caps, per-body material; beyond the paper, whose Section 4.1 takes a fixed stiffness and
/// damping per point).
///
/// @details Pure functions, no Bullet, no state:
/// - damping ratio from restitution, zeta(e) = -ln e / sqrt(pi^2 + ln^2 e) (zeta(0) = 1, critical), and back,
///   e(zeta) = exp(-zeta pi / sqrt(1 - zeta^2)) (0 for zeta >= 1): the rebound of a linear spring-dashpot that
///   lets go when its penetration returns to zero;
/// - Bullet's combine rules for a pair's materials (btManifoldResult: friction a b clamped to 10, restitution a b);
/// - the effective mass of a pair along a normal, 1/m_eff = sum over dynamic bodies of
///   1/m + (r x n)^T I^-1 (r x n) (btRigidBody::computeImpulseDenominator);
/// - the caps, applied per pair and step before integrating: with K the pair's total stiffness and
///   omega = sqrt(K / m_eff), the stiffness cap scales every k_i by (Omega_max / (omega dt))^2 when
///   omega dt > Omega_max (default 0.7); the damping C = 2 zeta sqrt(K m_eff) is shared as c_i = C k_i / K,
///   and the damping cap scales every c_i so that C dt / m_eff <= maxDampingDt (default 1; explicit damping
///   diverges at 2).
/// Every function throws sdfccd::Error (one line naming the parameter) on NaN or an out-of-range value.
#pragma once

#include "sdfccd/math_types.h"

namespace sdfccd {

/// Bullet's cap on a combined friction coefficient (btManifoldResult.cpp, MAX_FRICTION).
inline constexpr double kMaxCombinedFriction = 10.0;

/// zeta(e) = -ln e / sqrt(pi^2 + ln^2 e) for restitution e in (0, 1]; zeta(0) = 1 (critical). Dimensionless.
double dampingRatioFromRestitution(double restitution);
/// The inverse: e(zeta) = exp(-zeta pi / sqrt(1 - zeta^2)) for zeta in [0, 1), 0 for zeta >= 1 (no rebound).
double restitutionFromDampingRatio(double dampingRatio);

/// Bullet's default friction combine: a b, clamped to [0, kMaxCombinedFriction]. Inputs >= 0, finite.
double combineFriction(double frictionA, double frictionB);
/// Bullet's default restitution combine: a b. Inputs >= 0, finite.
double combineRestitution(double restitutionA, double restitutionB);

/// One body's term of 1/m_eff at a contact (1/kg): inverseMass + (r x n)^T inverseInertiaInWorld (r x n), r the
/// contact point minus the centre of mass (m), n the unit normal, all in world. Static, kinematic and sleeping
/// bodies contribute 0: pass inverseMass = 0 and a zero inverse inertia.
double inverseEffectiveMassTerm(double inverseMass, const Mat3& inverseInertiaInWorld, const Vec3& leverArmInWorld,
                                const Vec3& normalInWorld);

/// The per-pair stability caps (docs/design/contact-response.md, damping and stability caps).
struct StabilityCapSettings {
  double maxOmegaDt = 0.7;    ///< Omega_max: largest omega dt of a pair (dimensionless, > 0)
  double maxDampingDt = 1.0;  ///< largest C dt / m_eff of a pair (dimensionless, in (0, 2))

  /// Throws sdfccd::Error (one line naming the field) on a value out of range or NaN.
  void validate() const;
};

/// Largest stable pair stiffness (N/m): m_eff (Omega_max / dt)^2, with m_eff = 1 / inverseEffectiveMass
/// (1/kg, > 0) and dt (s, > 0).
double maxPairStiffness(double inverseEffectiveMass, double timeStep, double maxOmegaDt);
/// Largest stable pair damping (N s/m): maxDampingDt m_eff / dt.
double maxPairDamping(double inverseEffectiveMass, double timeStep, double maxDampingDt);

/// What the caps make of one pair's coefficients.
struct PairResponseCoefficients {
  double stiffnessScale = 1.0;       ///< multiply every k_i of the pair by it (dimensionless, in (0, 1])
  double dampingPerStiffness = 0.0;  ///< s: c_i = dampingPerStiffness * (scaled k_i)
  double totalStiffness = 0.0;       ///< N/m, the pair's K after the stiffness cap
  double totalDamping = 0.0;         ///< N s/m, the pair's C after the damping cap
  bool stiffnessCapped = false;      ///< the stiffness cap acted (count it in softenedPairs)
  bool dampingCapped = false;        ///< the damping cap acted
};

/// The pair's coefficients for one step (the caps above): totalStiffness K = sum of the pair's k_i (N/m, >= 0),
/// inverseEffectiveMass (1/kg, >= 0; 0 when no body of the pair is dynamic: no cap, no damping), dampingRatio
/// zeta (dimensionless, [0, 2]), timeStep dt (s, > 0).
PairResponseCoefficients pairResponseCoefficients(double totalStiffness, double inverseEffectiveMass,
                                                  double dampingRatio, double timeStep,
                                                  const StabilityCapSettings& settings = {});

}  // namespace sdfccd
