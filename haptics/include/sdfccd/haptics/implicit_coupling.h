/// @file
/// @brief The virtual coupling integrated implicitly with the simulated object (paper Section 4.1, admittance
/// mode), optionally with the device's own dynamics in the same backward Euler step.
///
/// @details One haptic tick of length h. The coupling wrench on the object F_c depends on the pose and twist
/// difference of device (x_h, v_h) and object (x_s, v_s); its gradients K = dF_c/dx_s and D = dF_c/dv_s
/// (virtual_coupling.h) give, to first order, the wrench at the end of the tick
///   F_c+ = F_c + K (dx_s - dx_h) + D (dv_s - dv_h),   dx = h (v + dv)   (the pose change of the tick).
/// The object takes one linearized backward Euler step under F_c+ and its contacts (F_t, gradient K_t):
///   M_s dv_s = h (F_c+ + F_t + K_t h (v_s + dv_s)).
/// - CouplingIntegration::Explicit: the default scheme, dx_h = 0 and dv_h = 0 in the object's step
///   (the device frozen for the tick) and the device rendered -F_c from the tick's start.
/// - Implicit (the paper's admittance mode, the object's side only): the device keeps its velocity over the
///   tick (dv_h = 0, dx_h = h v_h), and the device is rendered -F_c+, the coupling at the end of the object's
///   step: action and reaction of the same implicit spring. Needs nothing about the device.
/// - ImplicitWithDevice: where the device's model is known (the emulator: mass, inertia, viscous friction),
///   the device is a second body of the same backward Euler step:
///   M_h dv_h = h (F_own - F_c+),   F_own = -B v_h (its friction at the tick's start; the user's pull is not
///   known to the renderer and is left out of the prediction: it changes the predicted device motion by
///   h^2 F_user / m_h per tick, about 7 um for 2 N on 0.3 kg at 1 kHz).
///   The 12x12 system
///     [ M_s - hD - h^2 (K + K_t)   hD + h^2 K      ] [dv_s]   [ h (F_c + F_t + h (K + K_t) v_s - h K v_h) ]
///     [ hD + h^2 K                 M_h - hD - h^2 K] [dv_h] = [ h (F_own - F_c - h K v_s + h K v_h)       ]
///   is solved by LU, and the device is rendered -F_c+ at the predicted end states. A device that integrates
///   F_own + the rendered wrench with (symplectic) Euler, as the emulator does, then lands exactly where the
///   step predicted (for the linear spring; tested), so the coupling spring is implicit on both of its ends:
///   a stiff coupling cannot make the device's explicit integration unstable (k h^2 / m_h > 4 would).
/// Without contact and with a linear spring, ImplicitWithDevice is the backward Euler step of two masses joined
/// by a spring: momentum is kept and the relative mode's energy shrinks by 1 / (1 + h^2 k / mu) per tick (mu the
/// reduced mass; tested).
///
/// Fig. 10b (the peg, 2,000 points; `sdfccd bench haptics --fig10b [--fig10b-all-rungs] --fig10b-coupling ...`):
/// the coupling's integration does not set the peg's stability limit. The coupling
/// is soft next to the masses it joins (k_c h^2 / m = 0.04 for the 50 g peg, 0.0067 for the 0.3 kg device, against the
/// explicit bound 4), and the failures are contact events inside the object's own step (5-10 wall contacts; the peg's
/// velocity reverses and doubles per tick for 2-3 ticks while the rendered force is still ~0.1 N). Per rung from 1e6 to
/// 4e7 N/m, both penalty models fail on scattered rungs from 5e6 N/m on in every integration (stable on 8-13 of 17
/// rungs, continuous; 11-12, discrete), so "the largest stable k below two failures" is a property of single
/// trajectories: its ratio reads 1.58 (explicit), 0.32 (implicit), 1.58 (implicit-device).
#pragma once

#include <string>

#include "sdfccd/haptics/rigid_body_state.h"
#include "sdfccd/haptics/spatial_types.h"
#include "sdfccd/haptics/virtual_coupling.h"

namespace sdfccd::haptics {

enum class CouplingIntegration { Explicit, Implicit, ImplicitWithDevice };

/// "explicit", "implicit", "implicit-device".
const char* toString(CouplingIntegration integration);
/// Parses the names above. Throws sdfccd::Error on another name.
CouplingIntegration parseCouplingIntegration(const std::string& name);

/// What the renderer knows of the device's dynamics (ImplicitWithDevice; the emulator's DeviceSettings).
struct CouplingDeviceModel {
  double mass = 0.0;                    ///< kg
  Vec3 inertiaDiagonal = Vec3::Zero();  ///< kg m^2, body axes
  double linearFriction = 0.0;          ///< N s/m
  double angularFriction = 0.0;         ///< N m s/rad
};

/// Throws sdfccd::Error unless the model's mass and inertia are positive and finite and its friction finite and >= 0.
void checkCouplingDeviceModel(const CouplingDeviceModel& model);

/// The inputs of one coupled step.
struct CoupledStepInput {
  CouplingIntegration integration = CouplingIntegration::Implicit;  ///< Implicit or ImplicitWithDevice
  double timestep = 0.0;                                            ///< h, s
  Mat6 objectMass = Mat6::Identity();                               ///< M_s (world)
  Vec6 objectTwist = Vec6::Zero();                                  ///< v_s
  Vec6 contactWrench = Vec6::Zero();                                ///< F_t, acting during the tick
  Mat6 contactGradient = Mat6::Zero();                              ///< K_t = dF_t/dx_s
  const CouplingWrench* coupling = nullptr;                         ///< F_c, K, D at the tick's start
  const RigidBodyState* device = nullptr;                           ///< x_h, v_h
  const CouplingDeviceModel* deviceModel = nullptr;                 ///< ImplicitWithDevice only
};

/// The result: the object's velocity change, the device's predicted one, and the wrench to render (-F_c+).
struct CoupledStep {
  Vec6 objectVelocityChange = Vec6::Zero();
  Vec6 deviceVelocityChange = Vec6::Zero();  ///< 0 for Implicit (the device keeps its velocity)
  Vec6 wrenchOnDevice = Vec6::Zero();
  bool solved = true;  ///< false: the system was singular (non-finite solution); the caller falls back
};

/// One coupled step (see the file comment). Throws sdfccd::Error on a missing input or Explicit.
CoupledStep solveCoupledStep(const CoupledStepInput& input);

}  // namespace sdfccd::haptics
