/// @file
/// @brief The 6-DoF virtual coupling between the device (manipulandum) and the simulated object
/// (paper Section 4.1, refs. [44]-[46]).
///
/// @details A linear and an angular spring-damper join the device pose x_h and the simulation pose x_s.
/// The springs are linear in the 6-D pose difference (translation, rotation vector) up to x_max and
/// saturate beyond it: the force never exceeds F_max = k x_max (x_max about half a voxel, so the coupling
/// alone cannot push the object deeper than a shallow penetration), the torque never exceeds k_r theta_max.
/// Dampers act on the relative velocity and do not saturate.
/// The result carries the 6x6 gradients of the wrench on the simulated object with respect to its own pose
/// and twist, for implicit (linearized backward Euler) integration.
#pragma once

#include "sdfccd/haptics/rigid_body_state.h"
#include "sdfccd/haptics/spatial_types.h"

namespace sdfccd::haptics {

struct VirtualCouplingSettings {
  double linearStiffness = 500.0;  ///< k, N/m
  double linearDamping = 5.0;      ///< N s/m
  double angularStiffness = 0.5;   ///< N m/rad
  double angularDamping = 0.005;   ///< N m s/rad
  double maxDisplacement = 1e-3;   ///< x_max, m: the spring force saturates at k x_max
  double maxRotation = 0.05;       ///< rad: the spring torque saturates at k_r theta_max
};

struct CouplingWrench {
  Vec6 onSimulation = Vec6::Zero();   ///< N, N m: pulls the simulated object towards the device
  Vec6 onDevice = Vec6::Zero();       ///< N, N m: the reaction, rendered to the user (= -onSimulation)
  Mat6 poseGradient = Mat6::Zero();   ///< d onSimulation / d x_s (N/m, N m/rad blocks)
  Mat6 twistGradient = Mat6::Zero();  ///< d onSimulation / d v_s
  bool linearSaturated = false;
  bool angularSaturated = false;
};

/// The coupling wrench for the current states.
CouplingWrench couplingWrench(const RigidBodyState& device, const RigidBodyState& simulation,
                              const VirtualCouplingSettings& settings);

}  // namespace sdfccd::haptics
