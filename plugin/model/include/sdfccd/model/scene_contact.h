/// @file
/// @brief SceneContact: the contact settings of a scene file (key "contact"; README "Scene files").
#pragma once

#include "sdfccd/response/contact_mode.h"
#include "sdfccd/response/force_timing.h"
#include "sdfccd/response/penalty_model.h"

namespace sdfccd {

struct SceneContact {
  PenaltyModel model = PenaltyModel::Continuous;  ///< "model": continuous (Section 4.1) or discrete
  double stiffness = 2000.0;                      ///< N/m per point
  double damping = 5.0;                           ///< N s/m per point (used only with the "damping" effect)
  double friction = 0.5;  ///< Coulomb coefficient (used only with the "friction" effect; beyond the paper)
  int subintervals = 5;
  bool timeOfImpactClamp = true;  ///< continuous model only
  double toiDepthCells = 0.5;     ///< field cells
  bool useTree = true;
  ForceTiming forceTiming = ForceTiming::SameStep;  ///< when the penalty impulses act
  /// "mode": penalty (the paper's model, the default for now) or solver (Bullet's solver answers the contacts)
  SdfccdContactMode mode = SdfccdContactMode::Penalty;
  /// The paper's shell normal by default: robust where points sink deep (the field's gradient turns at thin
  /// parts: the 20-bunny drop's largest stable timestep is 2.5 ms with it, 1 ms with the gradient), but not
  /// conservative (a box resting on its 8 corner points drifts; tests/bullet/stability_test.cpp), where
  /// "field_gradient" is the choice.
  PenaltyDirection direction = PenaltyDirection::ShellNormal;  ///< "direction": shell_normal or field_gradient
};

}  // namespace sdfccd
