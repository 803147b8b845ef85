/// @file
/// @brief ForceTiming: when a step's penalty impulses reach the velocities (paper Section 4.1, eq. (5)).
///
/// @details A setting of its own, without Bullet, so that the scene schema (sdfccd/model/scene_contact.h) and the
/// Bullet contact system (sdfccd/bullet/contact_system.h) share it.
#pragma once

#include <cstdint>

namespace sdfccd {

/// When the step's penalty impulses reach the velocities.
enum class ForceTiming : std::uint8_t {
  /// Paper, Section 4.1 literally: I and M from the step's motion act over the *next* step (applied after
  /// integrateTransforms). The force lags the motion by half a step on average, which feeds energy into a
  /// stiff contact (for a linear spring the amplification per step is sqrt(1 + (omega dt)^2 / 2)); damping
  /// must absorb it.
  NextStep,
  /// Predictive: I and M are integrated over the step's predicted motion and applied at once, before
  /// Bullet integrates the step (a semi-implicit step: dissipative, stable for omega dt < 2).
  SameStep,
};

}  // namespace sdfccd
