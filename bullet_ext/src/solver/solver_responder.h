/// @file
/// @brief SolverResponder: solver mode's answer to a pair's roles (design note Sections 3.1 and 3.2; beyond the
/// paper). Each role's work (solver_role.h) is taken from the step's plan or computed here; its candidates are
/// collected over the pair's roles, and at the pair's end reduced and written into the pair's manifolds
/// (solver_manifolds.h) for Bullet's constraint solver.
#pragma once

#include "solver/solver_manifolds.h"
#include "solver/solver_role.h"
#include "step/pair_responder.h"
#include "step/step_data.h"

namespace sdfccd::bullet::detail {

class SolverResponder final : public RoleVisitorOf<SolverResponder, PairResponder> {
 public:
  explicit SolverResponder(StepData& data) : m_data(data) {}

  void beginPair(const PairCall& call) override;
  void applyPlanned(const RoleResult& result) override;
  /// Reduces the pair's candidates and writes its manifolds (not while the step is planned).
  void endPair() override;

  /// One role (RoleVisitor): its planned result, or its work computed now; its candidates are the pair's.
  template <class Field>
  void visitField(const Role& role, const Field& field, double cellSize);
  /// Planning: queues the role's work in the step's batch (GridField and PlaneField).
  template <class Field>
  void queue(const Role& role, const Field& field, double cellSize);

 private:
  /// The role's work with its inputs (solver_role.h).
  template <class Field>
  SolverRoleJob<Field> job(const Role& role, const Field& field, double cellSize) const;

  StepData& m_data;
  const PairCall* m_call = nullptr;
  SolverCandidates m_candidates;  // the current pair's, both roles
};

}  // namespace sdfccd::bullet::detail
