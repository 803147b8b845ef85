/// @file
/// @brief makeContactSolver and configureContactSolver (see sdfccd/bullet/contact_solver.h).
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/ConstraintSolver/btContactSolverInfo.h>
#include <BulletDynamics/ConstraintSolver/btNNCGConstraintSolver.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletDynamics/MLCPSolvers/btDantzigSolver.h>
#include <BulletDynamics/MLCPSolvers/btMLCPSolver.h>

#include "sdfccd/bullet/contact_solver.h"

namespace sdfccd::bullet {
namespace {

/// Measured (tests/bullet/textbook_solver_test.cpp, 10-box stack and 10 kg on 0.1 kg, 1/60 to 1/480 s): 1e-5 and
/// 1e-4 hold both; 1e-6 lets the stack move 1.75 mm at 1/60 s; 0 falls back to sequential impulse on 1 step in 5.
constexpr btScalar kMlcpGlobalCfm = btScalar(1e-5);

/// Owns the Dantzig solver so that it is built before the btMLCPSolver that keeps a pointer to it.
struct DantzigHolder {
  btDantzigSolver dantzig;
};

/// btMLCPSolver with Dantzig for islands up to kMlcpMaxRows rows; a larger island goes to sequential impulse
/// (set up and iterated as btSequentialImpulseConstraintSolver would, with the same solver info).
class BoundedMlcpSolver : private DantzigHolder, public btMLCPSolver {
 public:
  BoundedMlcpSolver() : btMLCPSolver(&dantzig) {}

 protected:
  btScalar solveGroupCacheFriendlySetup(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds,
                                        int numManifolds, btTypedConstraint** constraints, int numConstraints,
                                        const btContactSolverInfo& info, btIDebugDraw* draw) override {
    m_sequential = estimatedRows(manifolds, numManifolds, constraints, numConstraints, info) > kMlcpMaxRows;
    ++(m_sequential ? m_counts.sequentialIslands : m_counts.dantzigIslands);
    if (m_sequential) {
      return btSequentialImpulseConstraintSolver::solveGroupCacheFriendlySetup(
          bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, draw);
    }
    return btMLCPSolver::solveGroupCacheFriendlySetup(bodies, numBodies, manifolds, numManifolds, constraints,
                                                      numConstraints, info, draw);
  }

  btScalar solveGroupCacheFriendlyIterations(btCollisionObject** bodies, int numBodies,
                                             btPersistentManifold** manifolds, int numManifolds,
                                             btTypedConstraint** constraints, int numConstraints,
                                             const btContactSolverInfo& info, btIDebugDraw* draw) override {
    if (m_sequential) {
      return btSequentialImpulseConstraintSolver::solveGroupCacheFriendlyIterations(
          bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, draw);
    }
    return btMLCPSolver::solveGroupCacheFriendlyIterations(bodies, numBodies, manifolds, numManifolds, constraints,
                                                           numConstraints, info, draw);
  }

 public:
  MlcpSolverCounts counts() const {
    MlcpSolverCounts c = m_counts;
    c.dantzigFailures = getNumFallbacks();
    return c;
  }

 private:
  /// An upper bound of the island's rows: each manifold point gives a contact row and its friction rows, each
  /// joint at most 6 rows.
  static int estimatedRows(btPersistentManifold** manifolds, int numManifolds, btTypedConstraint**, int numConstraints,
                           const btContactSolverInfo& info) {
    const int perPoint = (info.m_solverMode & SOLVER_USE_2_FRICTION_DIRECTIONS) ? 3 : 2;
    int rows = 6 * numConstraints;
    for (int m = 0; m < numManifolds; ++m) rows += perPoint * manifolds[m]->getNumContacts();
    return rows;
  }

  bool m_sequential = false;
  MlcpSolverCounts m_counts;
};

}  // namespace

std::unique_ptr<btConstraintSolver> makeContactSolver(ContactSolver kind) {
  switch (kind) {
    case ContactSolver::Mlcp:
      return std::make_unique<BoundedMlcpSolver>();
    case ContactSolver::Nncg:
      return std::make_unique<btNNCGConstraintSolver>();
    case ContactSolver::SequentialImpulse:
      break;
  }
  return std::make_unique<btSequentialImpulseConstraintSolver>();
}

void configureContactSolver(btContactSolverInfo& info, ContactSolver kind) {
  if (kind != ContactSolver::Mlcp) return;
  info.m_globalCfm = kMlcpGlobalCfm;
  info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
  info.m_minimumSolverBatchSize = 1;
}

std::optional<MlcpSolverCounts> mlcpSolverCounts(const btConstraintSolver& solver) {
  const auto* mlcp = dynamic_cast<const BoundedMlcpSolver*>(&solver);
  if (mlcp == nullptr) return std::nullopt;
  return mlcp->counts();
}

const char* contactSolverName(ContactSolver kind) {
  switch (kind) {
    case ContactSolver::Mlcp:
      return "mlcp";
    case ContactSolver::Nncg:
      return "nncg";
    case ContactSolver::SequentialImpulse:
      break;
  }
  return "sequential_impulse";
}

}  // namespace sdfccd::bullet
