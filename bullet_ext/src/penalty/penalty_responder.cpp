/// @file
/// @brief PenaltyResponder (see penalty_responder.h).
#include "penalty/penalty_responder.h"

#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <cstring>
#include <type_traits>

#include "common/bullet_conversions.h"
#include "penalty/penalty_role.h"

namespace sdfccd::bullet::detail {

void PenaltyResponder::beginPair(const PairCall& call) {
  m_resultOut = call.resultOut;
  m_timeStep = call.timeStep;
  m_closestPointsOnly = call.closestPointsOnly;
}

PenaltyRoleFacts PenaltyResponder::facts(const Role& role, double cellSize, bool ground) const {
  // A planned role keeps pointers to what stays put through the step only: the bodies' motions (the steps are not
  // resized during the batch: the planner reserves them), the models' frames, the world's settings, and copies in
  // the batch's slots of what is the role's own.
  const ContactSettings& settings = m_data.settings;
  const bool closestPointsOnly = m_closestPointsOnly;
  PenaltyRoleFacts facts;
  facts.shell = &m_data.bodies[role.shell];
  facts.fieldBody = &m_data.bodies[role.field];
  facts.bodyFromShellChild = &role.bodyFromShellChild;
  facts.bodyFromFieldChild = &role.bodyFromFieldChild;
  facts.bodyFromField = &role.bodyFromField;
  facts.penalty = role.penalty != nullptr ? role.penalty : &settings.penalty;
  facts.anchors = role.anchors;
  facts.coherence = role.coherence;
  facts.shellIndex = role.shell;
  facts.fieldIndex = role.field;
  facts.timeStep = m_timeStep;
  facts.cellSize = cellSize;
  facts.thresholdCells = settings.toiDepthCells;
  facts.roleScale = role.roleScale;
  facts.friction = role.friction;
  facts.dampingRatio = role.dampingRatio;
  facts.octree = settings.octree;
  facts.maxManifoldPoints = settings.maxManifoldPoints;
  facts.useTree = settings.useTree;
  facts.shellIsBody0 = role.shellIsBody0;
  facts.closestPointsOnly = closestPointsOnly;
  facts.discreteModel = settings.penalty.model == PenaltyModel::Discrete;
  facts.timeOfImpactClamp = settings.timeOfImpactClamp;
  facts.shadowLinear = !closestPointsOnly && m_data.shadowStep() && !ground;
  facts.cpuClock = m_data.shadowLinearEvery > 0;
  facts.ground = ground;
  return facts;
}

template <class Field>
void PenaltyResponder::visitField(const Role& role, const Field& field, double cellSize) {
  // Computed in this step's parallel batch: apply it.
  if (const RoleResult* planned = m_data.takePlanned(role, kDeferrableField<Field>)) {
    apply(*planned, m_closestPointsOnly);
    return;
  }
  PenaltyRoleInput in;
  fillPenaltyInput(facts(role, cellSize, std::is_same_v<Field, PlaneField>), in);
  RoleResult& result = m_data.scratch();
  computePenaltyRole(*role.shellTree, field, in, result);
  apply(result, m_closestPointsOnly);
}

template <class Field>
void PenaltyResponder::queue(const Role& role, const Field& field, double cellSize) {
  // Filled in its slot (no copy of a local); what points into `role` (a local of the enumeration) is made to last.
  using Plan = PenaltyRolePlan<Field>;
  Plan& plan = m_data.deferred.slot<Plan>();
  plan.tree = role.shellTree;
  plan.field = HeldField<Field>(field);
  plan.facts = facts(role, cellSize, std::is_same_v<Field, PlaneField>);
  plan.facts.bodyFromShellChild = lastingFrame(role.bodyFromShellChild, nullptr);
  plan.facts.bodyFromFieldChild = lastingFrame(role.bodyFromFieldChild, nullptr);
  plan.facts.bodyFromField = lastingFrame(role.bodyFromField, role.modelBodyFromField);
  // The bodies' frames, kept for the step's other roles of the same bodies, when the child frames are ones whose
  // value never changes (the identity, the model's field frame; not a stashed copy, whose address may be reused).
  const Rigid* identity = &identityFrame();
  if (plan.facts.bodyFromShellChild == identity) {
    plan.facts.shellFrames = keptShellFrames(m_data.bodies[role.shell], identity);
  }
  if (plan.facts.bodyFromFieldChild == identity && role.modelBodyFromField != nullptr &&
      plan.facts.bodyFromField == role.modelBodyFromField) {
    plan.facts.fieldFrames = keptFieldFrames(m_data.bodies[role.field], identity, role.modelBodyFromField);
  }
  // Without per-body overrides the pair's parameters are the world's (BodyContacts::combined returns them untouched).
  plan.facts.penalty = m_data.bodyContacts.empty() || role.penalty == nullptr ? &m_data.settings.penalty
                                                                              : &m_data.deferred.stash(*role.penalty);
  const auto run = [](const void* data, RoleResult& out) {
    const Plan& p = *static_cast<const Plan*>(data);
    // One input per thread, reused: fillPenaltyInput writes the same fields for every role, unconditionally, and
    // nothing else writes any, so the rest keep their defaults as in a fresh one (building a fresh one per role,
    // about 1.2 KB of identity frames and default settings, is a measurable share of a pile's step).
    static thread_local PenaltyRoleInput in;
    fillPenaltyInput(p.facts, in);
    computePenaltyRole(*p.tree, p.field.get(), in, out);
  };
  // A refused query (the batch full: not with two roles per planned pair) is computed when Bullet reaches it; its
  // pair is then not applied as a whole (ContactStep::processPair).
  if (!m_data.deferred.add(role.manifold, role.index, run, &plan)) m_data.planIncomplete.push_back(role.manifold);
}

const Rigid* PenaltyResponder::lastingFrame(const Rigid& frame, const Rigid* kept) {
  const Rigid& identity = identityFrame();
  if (kept != nullptr) return kept;
  // Bit for bit: the job then computes with exactly these values.
  if (std::memcmp(frame.data(), identity.data(), sizeof(double) * 16) == 0) return &identity;
  return &m_data.deferred.stash(frame);
}

void PenaltyResponder::apply(const RoleResult& result, bool closestPointsOnly) {
  ContactStatistics& stats = m_data.stats;
  const RoleResult::PenaltySummary& summary = result.penalty;  // the query stayed on its thread
  stats.shadowLinearSeconds += result.shadowSeconds;
  stats.ccdSeconds += summary.ccdSeconds;
  if (result.ground) {
    stats.groundCcdSeconds += summary.ccdSeconds;
    ++stats.groundCcdQueries;
  }
  if (summary.coefficients.stiffnessCapped) ++stats.softenedPairs;
  ++stats.ccdQueries;
  stats.segmentQueries += summary.segmentQueries;
  if (!summary.touched) return;
  for (const RoleResult::ManifoldPoint& p : result.manifoldPoints) {
    m_resultOut->addContactPoint(toBt(p.normal), toBt(p.point), btScalar(p.depth));
  }
  if (closestPointsOnly || !result.hasRecord) return;
  m_data.records.push_back(result.record);  // one copy, into its place
  ContactRecord& record = m_data.records.back();
  stats.penaltySeconds += summary.penaltySeconds;
  stats.penaltySamples += record.penalty.samples;
  stats.dampingEvaluations += record.penalty.dampingEvaluations;
  stats.torqueEvaluations += record.penalty.torqueEvaluations;
  stats.frictionEvaluations += record.penalty.frictionEvaluations;
  m_data.loads.add(record, result.roleScale, summary.coefficients, m_data.bodies);
  // A kinematic pair keeps its penalty impulses (it is never rewound).
  if (m_data.settings.forceTiming == ForceTiming::SameStep &&
      (!record.clamp || record.action == ClampAction::KinematicPush)) {
    applyPenaltyImpulses(record, m_data.bodies);
    record.applied = true;
  }
}

void applyPenaltyImpulses(const ContactRecord& r, const BodySteps& bodies) {
  for (int side = 0; side < 2; ++side) {
    const BodyStep& step = bodies[side == 0 ? r.shell : r.field];
    btRigidBody* body = step.body;
    if (body == nullptr) continue;
    // Contact mass scaling (ContactLoads::applyContactMass): the body takes J m / m_c.
    const Vec3 impulse = step.contactMassScale * (side == 0 ? r.penalty.impulseOnShell : r.penalty.impulseOnField);
    const Vec3 angular =
        step.contactMassScale * (side == 0 ? r.penalty.angularImpulseOnShell : r.penalty.angularImpulseOnField);
    if (impulse.isZero(0.0) && angular.isZero(0.0)) continue;
    if (!impulse.allFinite() || !angular.allFinite()) continue;  // never spread a NaN (see nonFinitePairs)
    // No activate(): a body that is asleep has no `body` this step (motion_prediction.h).
    body->applyCentralImpulse(toBt(impulse));
    if (!angular.isZero(0.0)) body->applyTorqueImpulse(toBt(angular));
  }
}

// The role visitor's overrides (role.h) call visitField for each field a role may have.
#define SDFCCD_PENALTY_ROLE(Field) template void PenaltyResponder::visitField<Field>(const Role&, const Field&, double);
SDFCCD_FOR_EACH_ROLE_FIELD(SDFCCD_PENALTY_ROLE)
#undef SDFCCD_PENALTY_ROLE
template void PenaltyResponder::queue<GridField>(const Role&, const GridField&, double);
template void PenaltyResponder::queue<PlaneField>(const Role&, const PlaneField&, double);

}  // namespace sdfccd::bullet::detail
