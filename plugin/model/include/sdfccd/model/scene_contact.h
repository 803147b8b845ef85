/// @file
/// @brief SceneContact: the contact settings of a scene file (key "contact"; docs/scene-format.md).
#pragma once

#include "sdfccd/response/contact_mode.h"
#include "sdfccd/response/force_timing.h"
#include "sdfccd/response/penalty_model.h"

namespace sdfccd {

/// Bullet's constraint solver for a world in solver mode (scene key contact.solver; docs/bullet.md).
/// Mlcp (the default): btMLCPSolver with btDantzigSolver, an exact LCP per island (friction by findex), with a
/// small global CFM and two friction directions; it is what holds a 10-box stack and 10 kg on 0.1 kg, where
/// Gauss-Seidel at 10 iterations does not converge. SequentialImpulse: Bullet's default solver at Bullet's
/// defaults. Nncg: btNNCGConstraintSolver (unstable at 100:1 mass ratios; kept for comparison).
enum class ContactSolver { Mlcp, SequentialImpulse, Nncg };

/// New scenes get solver mode and, in penalty mode, the project's defaults (PenaltySettings::trustworthy()):
/// stiffness per unit area, damping from the pair's restitution, the Blend direction and anchor friction with mu
/// from the bodies. The paper's parameters stay available: "stiffness" (per point) replaces "stiffness_per_area",
/// "damping" (per point) replaces the damping ratio, and the paper's scenes name them with "mode": "penalty",
/// "direction": "shell_normal" and "friction_model": "regularized".
struct SceneContact {
  PenaltyModel model = PenaltyModel::Continuous;  ///< "model": continuous (Section 4.1) or discrete
  double stiffness = 2000.0;                      ///< "stiffness": N/m per point (when stiffnessPerArea is 0)
  double stiffnessPerArea = 1.0e7;                ///< "stiffness_per_area": N/m^3; 0 when "stiffness" is given
  double damping = 5.0;  ///< "damping": N s/m per point (with the "damping" effect, when dampingRatio < 0)
  /// "damping_ratio" zeta in [0, 2]; < 0: per-point damping when "damping" is given, else zeta from restitution.
  double dampingRatio = -1.0;
  bool dampingFromRestitution = true;  ///< neither "damping" nor "damping_ratio": zeta(e) of each pair
  double friction = 0.5;           ///< "friction": a pair override of mu (with the "friction" effect; beyond the paper)
  bool frictionFromBodies = true;  ///< no "friction" key: mu combined from the bodies (Bullet's rule)
  FrictionModel frictionModel = FrictionModel::Anchor;  ///< "friction_model": anchor or regularized
  int subintervals = 5;
  bool timeOfImpactClamp = true;  ///< continuous model only
  double toiDepthCells = 0.5;     ///< field cells
  bool useTree = true;
  ForceTiming forceTiming = ForceTiming::SameStep;  ///< when the penalty impulses act
  /// "mode": solver (the default: Bullet's solver answers the contacts; on the 20-bunny drop it has the larger
  /// stable step at a lower cost, docs/bullet.md) or penalty (the paper's model; the paper's scenes
  /// name it)
  SdfccdContactMode mode = SdfccdContactMode::Solver;
  /// "solver": mlcp, sequential_impulse or nncg (solver mode only; penalty mode keeps Bullet's default solver, which
  /// then sees no contacts of ours)
  ContactSolver solver = ContactSolver::Mlcp;
  /// Blend by default: the field's gradient while shallow (conservative: a box rests and slides as Coulomb says),
  /// the paper's shell normal past 2 cells (robust where points sink deep: the gradient turns at thin parts).
  PenaltyDirection direction = PenaltyDirection::Blend;  ///< "direction": blend, shell_normal or field_gradient
};

}  // namespace sdfccd
