/// @file
/// @brief The time-of-impact clamp's decisions and its impact, Bullet-free (beyond the paper;
/// docs/design/contact-response.md, kinematic bodies): what a pair whose points entered too deep during a step
/// does, and the sequential impulses that turn the entering points' approach into a rebound of the pair's
/// restitution.
///
/// @details Policy, decided here:
/// - a pair of two bodies that may move back (dynamic, awake) is rewound to the earliest deep entry
///   (ClampAction::Rewind) and its penalty impulses of the step are dropped;
/// - a pair with a kinematic body is never rewound (the kinematic cannot go back, and rewinding only the dynamic
///   body leaves it inside) and keeps its penalty impulses (ClampAction::KinematicPush): the impact uses the
///   kinematic's point velocity, and the dynamic body is pushed along the normal by what the kinematic advanced
///   after the hit (kinematicPushDistance);
/// - static and sleeping bodies have infinite mass and zero velocity in the impact.
/// Bodies are described by ImpactBody (inverse mass 0: infinite mass; its velocity still counts).
#pragma once

#include <cstdint>
#include <vector>

#include "sdfccd/math_types.h"

namespace sdfccd {

/// What a clamping pair does.
enum class ClampAction : std::uint8_t {
  None,           ///< no deep entry: the penalty forces alone
  Rewind,         ///< rewind the movable bodies to the first deep hit, impact impulse, drop the penalty impulses
  KinematicPush,  ///< a kinematic body: no rewind, impact impulse with its velocity, push, keep penalty impulses
};

/// The clamp's policy for a pair with deep entries (`deepEntry`), given whether either body is kinematic.
ClampAction clampAction(bool deepEntry, bool shellKinematic, bool fieldKinematic);

/// One body in the impact, world quantities at the clamp.
struct ImpactBody {
  double inverseMass = 0.0;                   ///< 1/kg (0: static, kinematic or asleep)
  Mat3 inverseInertiaInWorld = Mat3::Zero();  ///< 1/(kg m^2)
  Vec3 centerOfMass = Vec3::Zero();           ///< m, world
  Vec3 linearVelocity = Vec3::Zero();         ///< m/s (a kinematic body's own velocity)
  Vec3 angularVelocity = Vec3::Zero();        ///< rad/s

  /// Velocity of the body's material point at `pointInWorld` (m/s).
  Vec3 pointVelocity(const Vec3& pointInWorld) const {
    return linearVelocity + angularVelocity.cross(pointInWorld - centerOfMass);
  }
};

/// One entering point: where it is (world, m) and the unit normal along which the shell body may move away
/// from the field body.
struct ImpactPoint {
  Vec3 pointInWorld = Vec3::Zero();
  Vec3 normalInWorld = Vec3::Zero();
};

/// What the impact did.
struct ImpactResult {
  Vec3 impulseOnShell = Vec3::Zero();  ///< N s, sum over the points (minus it on the field)
  int activePoints = 0;                ///< points that ended with a positive accumulated impulse
};

/// Sequential impulses (`iterations` sweeps; accumulated impulse per point kept >= 0) after which each of the
/// shell's points leaves the field body's material point at `restitution` times the normal speed it approached
/// with (0: the approaching normal velocity is removed, a plastic impact); updates the velocities of `shell` and
/// `field` in place (bodies of inverse mass 0 keep theirs).
ImpactResult resolveImpact(const std::vector<ImpactPoint>& points, ImpactBody& shell, ImpactBody& field,
                           double restitution = 0.0, int iterations = 8);

/// How far (m, world) the dynamic body must move along `normalInWorld` (unit, pointing from the kinematic body
/// to the dynamic one) to follow what the kinematic body advanced after the hit: ((1 - hitFraction) dt v_K . n) n
/// when positive, else zero.
Vec3 kinematicPushDistance(const Vec3& kinematicVelocity, const Vec3& normalInWorld, double hitFraction,
                           double timeStep);

}  // namespace sdfccd
