/// @file
/// @brief The constraint solver for a Bullet world whose SdfccdShapes run in solver mode (docs/bullet.md,
/// "Which constraint solver, and why").
///
/// @details Solver mode hands the CCD's contacts to Bullet's constraint solver as manifold points. Bullet's
/// default btSequentialImpulseConstraintSolver (Gauss-Seidel, 10 iterations) does not converge on a stack of ten
/// boxes or a 100:1 mass ratio: its unconverged answer lets such a stack creep by millimetres, with Bullet's own
/// btBoxShapes as with ours. ContactSolver::Mlcp solves each island's contacts exactly (btMLCPSolver with
/// btDantzigSolver: a mixed LCP whose friction rows are bounded by mu times their contact's impulse). It needs
///  - a small global CFM (1e-5, added as CFM/dt to the LCP's diagonal): the rows of a box's face contacts are
///    linearly dependent, and without regularisation Dantzig fails on about 1 step in 5 and Bullet falls back to
///    sequential impulse for that step;
///  - two friction directions per point: with Bullet's single row, whose direction follows the sliding velocity,
///    the sideways motion is free within a step, and a column creeps sideways even under an exact solver;
///  - one island per solve (m_minimumSolverBatchSize 1): Bullet batches small islands together by default, which
///    only makes the LCP larger (its cost grows with the cube of the rows).
/// A Bullet user building their own world:
/// @code
///   auto solver = sdfccd::bullet::makeContactSolver(sdfccd::ContactSolver::Mlcp);
///   btDiscreteDynamicsWorld world(&dispatcher, &broadphase, solver.get(), &configuration);
///   sdfccd::bullet::configureContactSolver(world.getSolverInfo(), sdfccd::ContactSolver::Mlcp);
/// @endcode
#pragma once

#include <memory>
#include <optional>

#include "sdfccd/model/scene_contact.h"

class btConstraintSolver;
struct btContactSolverInfo;

namespace sdfccd::bullet {

/// Largest island (in solver rows: one per contact point and friction direction, plus the joints' rows) that the
/// Mlcp solver answers with Dantzig; a larger island is answered by sequential impulse. The LCP's cost grows with the
/// cube of its rows: measured on pyramids of btBoxShapes at 1/240 s, 3.4 ms per step at 300 rows, 63 ms at 770 and
/// 530 ms at 1,450 (sequential impulse: 0.05 to 0.27 ms), so 400 rows cost at most about 8 ms a step. The solver
/// textbook scenes stay below it (the 15-box pyramid: 303 rows at most, the 20-bunny pile 231).
constexpr int kMlcpMaxRows = 400;

/// The solver for `kind` (Mlcp: Dantzig up to kMlcpMaxRows per island, sequential impulse above).
std::unique_ptr<btConstraintSolver> makeContactSolver(ContactSolver kind);

/// Sets in `info` what `kind` needs (Mlcp: the global CFM, two friction directions, one island per solve; the
/// others keep Bullet's defaults).
void configureContactSolver(btContactSolverInfo& info, ContactSolver kind);

/// What an Mlcp solver did so far, island by island (solves, not steps).
struct MlcpSolverCounts {
  long dantzigIslands = 0;     ///< islands answered by Dantzig (including those where it failed)
  long dantzigFailures = 0;    ///< of those, islands where Dantzig failed and Bullet fell back to sequential impulse
  long sequentialIslands = 0;  ///< islands above kMlcpMaxRows, answered by sequential impulse
};

/// The counts of a solver made by makeContactSolver(ContactSolver::Mlcp); nullopt for any other solver.
std::optional<MlcpSolverCounts> mlcpSolverCounts(const btConstraintSolver& solver);

/// "mlcp", "sequential_impulse" or "nncg" (the scene key's values).
const char* contactSolverName(ContactSolver kind);

}  // namespace sdfccd::bullet
