/// @file
/// @brief RunawayGuard: energy, speed and distance bounds of a running scene (runaway_guard.h).
#include "sdfccd/model/runaway_guard.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace sdfccd {
namespace {

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

RunawayGuard::RunawayGuard(const Scene& scene, double initialKineticEnergy) : m_limits(scene.guard) {
  if (scene.has("gravity")) m_gravity = scene.gravity;
  const double g = m_gravity.norm();
  const Vec3 up = g > 0.0 ? Vec3(-m_gravity / g) : Vec3::Zero();
  // The lowest point potential energy is measured from: the lowest body centre, or the ground plane.
  double lowest = 0.0;
  bool haveLowest = false;
  if (scene.has("ground")) {
    lowest = up.dot(Vec3(0.0, scene.groundHeight, 0.0));
    haveLowest = true;
  }
  for (const SceneBody& b : scene.bodies) {
    const double height = up.dot(b.position);
    lowest = haveLowest ? std::min(lowest, height) : height;
    haveLowest = true;
    m_extent = std::max(m_extent, b.position.norm());
    if (b.kinematic) {
      // A point of a kinematic body moves at |v| + |w| r; r up to the scene's extent is a generous stand-in.
      m_kinematicSpeed = std::max(m_kinematicSpeed, b.velocity.norm() + b.angularVelocity.norm() * m_extent);
    }
  }
  double potential = 0.0;
  double massSum = 0.0;
  for (const SceneBody& b : scene.bodies) {
    const bool dynamic = !b.isStatic && !b.kinematic;
    m_names.push_back(b.name);
    m_masses.push_back(dynamic ? b.mass : 0.0);
    m_startPositions.push_back(b.position);
    if (!dynamic) continue;
    massSum += b.mass;
    potential += b.mass * g * (up.dot(b.position) - lowest);
    m_startSpeed = std::max(m_startSpeed, b.velocity.norm());
  }
  const double kinematicEnergy = 0.5 * massSum * 4.0 * m_kinematicSpeed * m_kinematicSpeed;
  const double floorEnergy = 0.5 * massSum * 1.0;  // every body at 1 m/s
  m_baseEnergy = std::max(0.0, initialKineticEnergy) + potential + kinematicEnergy + floorEnergy;
}

double RunawayGuard::energyBound(const std::vector<GuardBodyState>& bodies) const {
  // The work gravity has done so far: exact, since gravity is conservative (sum m g.(x - x0)).
  double gravityWork = 0.0;
  for (std::size_t i = 0; i < bodies.size() && i < m_masses.size(); ++i) {
    gravityWork += m_masses[i] * m_gravity.dot(bodies[i].position - m_startPositions[i]);
  }
  return m_limits.energyFactor * (m_baseEnergy + std::max(0.0, gravityWork));
}

double RunawayGuard::speedBound(double time) const {
  return m_limits.maxSpeed + m_startSpeed + 2.0 * m_kinematicSpeed + m_gravity.norm() * time;
}

double RunawayGuard::distanceBound(double time) const {
  return m_limits.extentFactor * m_extent + (m_startSpeed + 2.0 * m_kinematicSpeed) * time +
         0.5 * m_gravity.norm() * time * time;
}

std::optional<std::string> RunawayGuard::check(double time, const std::vector<GuardBodyState>& bodies,
                                               double kineticEnergy) const {
  if (m_limits.action == GuardAction::Off) return std::nullopt;
  const std::string at = " (t = " + number(time) + " s)";
  auto body = [&](std::size_t i) {
    return "body '" + (i < m_names.size() ? m_names[i] : std::string("?")) + "' (bodies[" + std::to_string(i) + "])";
  };
  const double speedLimit = speedBound(time);
  const double distanceLimit = distanceBound(time);
  std::size_t mostEnergetic = 0;
  double largest = -1.0;
  for (std::size_t i = 0; i < bodies.size() && i < m_masses.size(); ++i) {
    if (m_masses[i] == 0.0) continue;  // static and kinematic bodies move as the scene says
    const GuardBodyState& s = bodies[i];
    if (!s.position.allFinite() || !s.velocity.allFinite()) return body(i) + " has a non-finite state" + at;
    const double speed = s.velocity.norm();
    if (speed > speedLimit) {
      return body(i) + " moves at " + number(speed) + " m/s, above the guard's bound of " + number(speedLimit) +
             " m/s" + at;
    }
    const double distance = s.position.norm();
    if (distance > distanceLimit) {
      return body(i) + " is " + number(distance) + " m from the origin, beyond the guard's bound of " +
             number(distanceLimit) + " m" + at;
    }
    const double energy = 0.5 * m_masses[i] * speed * speed;
    if (energy > largest) {
      largest = energy;
      mostEnergetic = i;
    }
  }
  if (!std::isfinite(kineticEnergy)) return "the kinetic energy is not finite" + at;
  const double energyLimit = energyBound(bodies);
  if (kineticEnergy > energyLimit) {
    return "the kinetic energy " + number(kineticEnergy) + " J is above the guard's bound of " + number(energyLimit) +
           " J (" + number(m_limits.energyFactor) +
           " times the scene's energy budget; fastest: " + body(mostEnergetic) + ")" + at;
  }
  return std::nullopt;
}

}  // namespace sdfccd
