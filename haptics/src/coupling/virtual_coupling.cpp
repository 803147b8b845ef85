/// @file
/// @brief The saturating 6-DoF virtual coupling (paper Section 4.1).
#include "sdfccd/haptics/virtual_coupling.h"

namespace sdfccd::haptics {

namespace {

// Spring along a 3-D displacement d saturating at |d| = dMax; writes the gradient w.r.t. d.
Vec3 saturatingSpring(const Vec3& d, double k, double dMax, Mat3& outGradient, bool& outSaturated) {
  const double len = d.norm();
  if (len <= dMax || !(dMax > 0.0)) {
    outSaturated = false;
    outGradient = k * Mat3::Identity();
    return k * d;
  }
  outSaturated = true;
  const Vec3 u = d / len;
  // F = k dMax u: only the direction changes with d.
  outGradient = (k * dMax / len) * (Mat3::Identity() - u * u.transpose());
  return (k * dMax) * u;
}

}  // namespace

CouplingWrench couplingWrench(const RigidBodyState& device, const RigidBodyState& simulation,
                              const VirtualCouplingSettings& settings) {
  CouplingWrench w;
  const Vec6 d = poseDifference(simulation.worldFromBody, device.worldFromBody);  // x_h - x_s
  Mat3 gLinear;
  Mat3 gAngular;
  const Vec3 f =
      saturatingSpring(d.head<3>(), settings.linearStiffness, settings.maxDisplacement, gLinear, w.linearSaturated);
  const Vec3 t =
      saturatingSpring(d.tail<3>(), settings.angularStiffness, settings.maxRotation, gAngular, w.angularSaturated);
  w.onSimulation.head<3>() = f + settings.linearDamping * (device.linearVelocity - simulation.linearVelocity);
  w.onSimulation.tail<3>() = t + settings.angularDamping * (device.angularVelocity - simulation.angularVelocity);
  w.onDevice = -w.onSimulation;
  // d/dx_s of the spring is minus its gradient w.r.t. the difference.
  w.poseGradient.topLeftCorner<3, 3>() = -gLinear;
  w.poseGradient.bottomRightCorner<3, 3>() = -gAngular;
  w.twistGradient.topLeftCorner<3, 3>() = -settings.linearDamping * Mat3::Identity();
  w.twistGradient.bottomRightCorner<3, 3>() = -settings.angularDamping * Mat3::Identity();
  return w;
}

}  // namespace sdfccd::haptics
