/// @file
/// @brief RunawayGuard: the physical sanity check of a running scene: a run whose state explodes stops with one
/// line naming the body instead of ending "successfully" with 1e18 J of kinetic energy.
///
/// @details Bullet-free: the caller (sdfccd simulate, a test) passes the bodies' centre-of-mass states each frame
/// in the order of scene.bodies. Three bounds, each generous (SceneGuard's factors, 1000 by default) around what
/// physics allows:
/// - energy: kinetic energy <= energyFactor * (E0 + W_gravity(t)+ + E_kinematic + E_floor), where E0 is the
///   initial kinetic energy plus the potential energy above the lowest point (the lowest body centre, or the
///   ground), W_gravity(t) = sum m g.(x(t) - x(0)) the work gravity has done so far (exact: gravity is
///   conservative), E_kinematic = sum 1/2 m (2 V)^2 with V the fastest kinematic body (a moving wall can give a
///   body at most twice its speed per bounce), and E_floor = sum 1/2 m (1 m/s)^2 so that a scene starting at rest
///   with nothing above the ground has a budget.
/// - speed: |v| <= maxSpeed + v0 + 2 V + |g| t (v0: the fastest start speed).
/// - distance: |x| <= extentFactor * extent + (v0 + 2 V) t + 1/2 |g| t^2, extent = max(0.1 m, the largest
///   start distance of a body centre from the origin).
/// Non-finite states are the NaN check's job (SceneWorld::hasNonFinite) and are reported here as a violation too.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/model/scene.h"

namespace sdfccd {

/// A body's motion as the guard sees it (centre of mass, world).
struct GuardBodyState {
  Vec3 position = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
};

class RunawayGuard {
 public:
  /// The budgets of `scene` (start poses and velocities, gravity with the "gravity" effect, the ground with
  /// "ground"); `initialKineticEnergy` includes rotation (SceneWorld::kineticEnergy() before the first step).
  RunawayGuard(const Scene& scene, double initialKineticEnergy);

  /// Nothing when `bodies` (one per scene body, in order) at `time` (s) with total kinetic energy
  /// `kineticEnergy` (J) is inside the bounds; else one line naming the body, the quantity, the value and the
  /// bound, e.g. "body 'box' (bodies[0]) moves at 1.2e+05 m/s, above the guard's bound of 1000 m/s (t = 0.012 s)".
  std::optional<std::string> check(double time, const std::vector<GuardBodyState>& bodies, double kineticEnergy) const;

  /// The energy bound (J) at `time` for `bodies` (for reports and tests).
  double energyBound(const std::vector<GuardBodyState>& bodies) const;
  double speedBound(double time) const;     ///< m/s
  double distanceBound(double time) const;  ///< m

 private:
  SceneGuard m_limits;
  std::vector<std::string> m_names;
  Vec3 m_gravity = Vec3::Zero();  ///< zero without the "gravity" effect
  std::vector<double> m_masses;   ///< 0 for static and kinematic bodies
  std::vector<Vec3> m_startPositions;
  double m_baseEnergy = 0.0;      ///< E0 + E_kinematic + E_floor (J)
  double m_startSpeed = 0.0;      ///< v0 (m/s)
  double m_kinematicSpeed = 0.0;  ///< V (m/s)
  double m_extent = 0.1;          ///< m
};

}  // namespace sdfccd
