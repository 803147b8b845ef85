/// @file
/// @brief Solver mode, one role's work that touches no Bullet object (see solver_role.cpp): its inputs, by value,
/// and the work itself, run on the narrowphase pool in a planned step or on the stepping thread.
#pragma once

#include <cstddef>

#include "parallel/deferred_queries.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/ccd/rigid_ccd_coherence.h"
#include "sdfccd/math_types.h"
#include "sdfccd/response/penalty_model.h"
#include "sdfccd/shell/point_tree.h"

namespace sdfccd::bullet::detail {

/// What a solver role's work reads, by value (it may run later, on the pool).
struct SolverRoleInput {
  Rigid sdfFromShellStart = Rigid::Identity();
  Rigid sdfFromShellEnd = Rigid::Identity();
  Rigid worldFromSdfStart = Rigid::Identity();
  Rigid worldFromShellStart = Rigid::Identity();
  Rigid shellStart = Rigid::Identity();  // the bodies' centre-of-mass frames at the step's start and end
  Rigid shellEnd = Rigid::Identity();
  Rigid fieldStart = Rigid::Identity();
  Rigid fieldEnd = Rigid::Identity();
  BodyVelocities shellVelocity;
  BodyVelocities fieldVelocity;
  RigidCcdSettings ccd;
  RigidCcdCoherence* coherence = nullptr;  // the pair and role's history: this role's job alone touches it
  double margin = 0.0;                     // m, the speculative margin
  double restitution = 0.0;                // the pair's combined restitution
  double timeStep = 0.0;                   // s
  double cellSize = 0.0;                   // m, for the record's penetration in cells
  std::size_t shell = 0;                   // body indices, for the record
  std::size_t field = 0;
  bool shellIsManifoldBody0 = true;
  bool ground = false;    // passed on to the result (RoleResult)
  bool cpuClock = false;  // time the CCD on the thread's CPU clock (ccdClock)
};

/// A solver role's work as queued: the shell's tree, the field (HeldField), the inputs.
template <class Field>
struct SolverRoleJob {
  const PointTree* tree;
  HeldField<Field> field;
  SolverRoleInput input;
};

/// The CCD with the speculative margin and each listed point as a candidate at the step's start (normals on the
/// manifold's body 1), into `out` (instantiated for every field a role may have).
template <class Field>
void computeSolverRole(const PointTree& tree, const Field& field, const SolverRoleInput& in, RoleResult& out);

}  // namespace sdfccd::bullet::detail
