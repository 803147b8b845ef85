/// @file
/// @brief SolverResponder (see solver_responder.h).
#include "solver/solver_responder.h"

#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>

#include <algorithm>
#include <type_traits>

#include "solver/solver_role.h"

namespace sdfccd::bullet::detail {

void SolverResponder::beginPair(const PairCall& call) {
  m_call = &call;
  m_candidates.points.clear();
  m_candidates.bounce.clear();
  m_candidates.distance.clear();
  m_candidates.margin = 0.0;
}

template <class Field>
SolverRoleJob<Field> SolverResponder::job(const Role& role, const Field& field, double cellSize) const {
  const ContactSettings& settings = m_data.settings;
  const BodyStep& shell = m_data.bodies[role.shell];
  const BodyStep& fieldBody = m_data.bodies[role.field];
  SolverRoleJob<Field> job{role.shellTree, HeldField<Field>(field), {}};
  SolverRoleInput& in = job.input;
  in.margin = std::min(settings.speculativeMarginCells * cellSize, settings.maxSpeculativeMargin);
  // A compound child's shell and field sit at their child frames in their bodies (bodyFrom*Child).
  const Rigid bodyFromSdf = role.bodyFromFieldChild * role.bodyFromField;
  in.worldFromSdfStart = fieldBody.worldFromBodyStart * bodyFromSdf;
  const Rigid worldFromSdfEnd = fieldBody.worldFromBodyEnd * bodyFromSdf;
  in.worldFromShellStart = shell.worldFromBodyStart * role.bodyFromShellChild;
  in.sdfFromShellStart = in.worldFromSdfStart.inverse() * in.worldFromShellStart;
  in.sdfFromShellEnd = worldFromSdfEnd.inverse() * shell.worldFromBodyEnd * role.bodyFromShellChild;
  in.shellStart = shell.worldFromBodyStart;
  in.shellEnd = shell.worldFromBodyEnd;
  in.fieldStart = fieldBody.worldFromBodyStart;
  in.fieldEnd = fieldBody.worldFromBodyEnd;
  in.shellVelocity = shell.velocity;
  in.fieldVelocity = fieldBody.velocity;
  in.restitution = double(gCalculateCombinedRestitutionCallback(shell.object, fieldBody.object));
  in.timeStep = m_call->timeStep;
  in.cellSize = cellSize;
  in.shell = role.shell;
  in.field = role.field;
  in.shellIsManifoldBody0 = role.shellIsBody0 != m_call->swapped;
  in.ground = std::is_same_v<Field, PlaneField>;
  in.cpuClock = m_data.shadowLinearEvery > 0;
  in.ccd.sigma = in.margin;
  in.ccd.mode = CcdMode::FirstHit;
  in.ccd.octree = settings.octree;
  in.ccd.useTree = settings.useTree;
  in.ccd.threads = 1;
  in.coherence = role.coherence;
  return job;
}

template <class Field>
void SolverResponder::visitField(const Role& role, const Field& field, double cellSize) {
  // Computed in this step's parallel batch: apply it.
  if (const RoleResult* planned = m_data.takePlanned(role, kDeferrableField<Field>)) {
    applyPlanned(*planned);
    return;
  }
  const SolverRoleJob<Field> work = job(role, field, cellSize);
  RoleResult& result = m_data.scratch();
  computeSolverRole(*work.tree, work.field.get(), work.input, result);
  applyPlanned(result);
}

template <class Field>
void SolverResponder::queue(const Role& role, const Field& field, double cellSize) {
  // The work holds copies of its inputs, stashed for the step (deferred_queries.h): the closure holds a pointer.
  const SolverRoleJob<Field>& kept = m_data.deferred.stash(job(role, field, cellSize));
  // A refused query (the batch full: not with two roles per planned pair) is computed when Bullet reaches it; its
  // pair is then not applied as a whole (ContactStep::processPair).
  if (!m_data.deferred.add(role.manifold, role.index, [&kept](RoleResult& out) {
        computeSolverRole(*kept.tree, kept.field.get(), kept.input, out);
      })) {
    m_data.planIncomplete.push_back(role.manifold);
  }
}

void SolverResponder::applyPlanned(const RoleResult& result) {
  ContactStatistics& stats = m_data.stats;
  m_candidates.margin = std::max(m_candidates.margin, result.margin);
  const double seconds = result.query.ccdSeconds;
  stats.ccdSeconds += seconds;
  if (result.ground) {
    stats.groundCcdSeconds += seconds;
    ++stats.groundCcdQueries;
  }
  ++stats.ccdQueries;
  stats.segmentQueries += result.query.ccd.stats.segmentQueries;
  if (!result.hasRecord) return;
  m_candidates.points.insert(m_candidates.points.end(), result.candidates.begin(), result.candidates.end());
  m_candidates.bounce.insert(m_candidates.bounce.end(), result.bounce.begin(), result.bounce.end());
  m_candidates.distance.insert(m_candidates.distance.end(), result.distance.begin(), result.distance.end());
  m_data.records.push_back(result.record);
}

void SolverResponder::endPair() {
  const PairCall& call = *m_call;
  const PenaltySettings& penalty = m_data.settings.penalty;
  const SolverFriction friction{penalty.enableFriction, penalty.frictionFromBodies, penalty.friction};
  writeSolverManifolds(call.swapped ? call.wrap1 : call.wrap0, call.swapped ? call.wrap0 : call.wrap1, call.manifold,
                       *call.solverPair, m_candidates, friction);
}

#define SDFCCD_SOLVER_RESPONSE(Field) template void SolverResponder::visitField<Field>(const Role&, const Field&, double);
SDFCCD_FOR_EACH_ROLE_FIELD(SDFCCD_SOLVER_RESPONSE)
#undef SDFCCD_SOLVER_RESPONSE
template void SolverResponder::queue<GridField>(const Role&, const GridField&, double);
template void SolverResponder::queue<PlaneField>(const Role&, const PlaneField&, double);

}  // namespace sdfccd::bullet::detail
