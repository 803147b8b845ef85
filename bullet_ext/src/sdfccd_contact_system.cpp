/// @file
/// @brief SdfccdContactSystem's narrowphase (Section 4.1 and 5; see sdfccd_contact_system.h): each body's
/// motion over the step, each pair's roles, queryContacts per role, manifold points and the clamping decision.
/// Settings and registration are in sdfccd_contact_settings.cpp, the step's parallel plan in
/// sdfccd_parallel_step.cpp, the response after integrateTransforms in sdfccd_contact_response.cpp, the convex
/// shapes' surface points in sdfccd_convex_shells.cpp.
#include "sdfccd/bullet/sdfccd_contact_system.h"

#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btEmptyCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <LinearMath/btTransformUtil.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <type_traits>

#include "bullet_conversions.h"
#include "bullet_shape_fields.h"
#include "contact_step.h"
#include "convex_fields.h"
#include "motion_prediction.h"
#include "narrowphase_pool.h"
#include "parallel_step.h"
#include "penalty_role.h"
#include "resting_pairs.h"
#include "sdfccd/bullet/sdfccd_collision_algorithm.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/response/contact_material.h"

namespace sdfccd {

using detail::kMaxClampPoints;
using detail::ShapeKind;
using detail::toBt;
using detail::toRigid;
using detail::toVec3;
using detail::withConvexField;

SdfccdContactSystem::SdfccdContactSystem(const SdfccdContactSettings& settings)
    : m_convexShapes(std::make_unique<detail::ConvexShapeCache>()),
      m_log([](const std::string& line) { std::cerr << line << '\n'; }),
      m_deferred(std::make_unique<detail::DeferredQueries>()) {
  setSettings(settings);
}

SdfccdContactSystem::~SdfccdContactSystem() = default;

SdfccdContactSystem::BodyStep& SdfccdContactSystem::bodyStep(const btCollisionObjectWrapper* wrap, double timeStep,
                                                             bool contactMass) {
  const btCollisionObject* object = wrap->getCollisionObject();
  // Asked twice per pair (an 80-body pile: ~2,000 times per step): the guess by world index spares most lookups
  // of the map, which stays the one record of which objects have their step (m_bodies holds each object once).
  const int worldIndex = object->getWorldArrayIndex();
  const auto guess = static_cast<std::size_t>(worldIndex);
  if (worldIndex >= 0 && guess < m_bodyGuess.size() && m_bodyGuess[guess] < m_bodies.size() &&
      m_bodies[m_bodyGuess[guess]].object == object) {
    return m_bodies[m_bodyGuess[guess]];
  }
  const auto found = m_bodyIndex.find(object);
  if (found != m_bodyIndex.end()) {
    if (worldIndex >= 0 && guess < m_bodyGuess.size()) m_bodyGuess[guess] = found->second;
    return m_bodies[found->second];
  }
  const detail::PredictedMotion motion = detail::predictBodyMotion(*object, timeStep);
  BodyStep step;
  step.object = object;
  step.body = motion.dynamicBody;
  step.kinematic = motion.kinematic;
  step.worldFromBodyStart = motion.worldFromBodyStart;
  step.worldFromBodyEnd = motion.worldFromBodyEnd;
  step.velocity = motion.velocity;
  step.mass = motion.mass;
  if (contactMass) applyContactMass(step, timeStep);  // not for a closest-point query: it changes velocities
  step.finiteState = step.finite();
  if (worldIndex >= 0) {
    if (guess >= m_bodyGuess.size()) m_bodyGuess.resize(guess + 1, std::size_t(-1));
    m_bodyGuess[guess] = m_bodies.size();
  }
  m_bodyIndex.emplace(object, m_bodies.size());
  m_bodies.push_back(step);
  return m_bodies.back();
}

SdfccdContactSystem::AnchorSlot& SdfccdContactSystem::anchorSlot(const btPersistentManifold* manifold, int role,
                                                                 const btCollisionObject* shell,
                                                                 const btCollisionObject* field) {
  // Bullet walks its pairs in the same order step after step, so the slot after the last one found is tried first
  // (a hashed lookup misses the cache three times; an 80-body pile looks up ~2,000 slots per step).
  const SlotKey key{manifold, role};
  AnchorSlot* slot = nullptr;
  // Written field by field in place, which is cheaper than copying a SlotVisit{...} temporary into the vector.
  const auto recordVisit = [&] {
    SlotVisit& visit = m_slotOrder.emplace_back();
    visit.key = key;
    visit.slot = slot;
    visit.shellObject = shell;
    visit.fieldObject = field;
    visit.step = m_stepCounter;
  };
  if (m_slotCursor < m_lastSlotOrder.size() && m_lastSlotOrder[m_slotCursor].key == key) {
    const SlotVisit& last = m_lastSlotOrder[m_slotCursor];
    slot = last.slot;
    if (last.step + 1 == m_stepCounter && last.shellObject == shell && last.fieldObject == field) {
      // Met at this place of last step's walk, with the same objects: it keeps its table and history. Decided from
      // the walk's own (sequential) record: the slot is only written here, and its cache line is often cold.
      ++m_slotCursor;
      slot->lastStep = m_stepCounter;
      slot->order = m_slotOrder.size();
      recordVisit();
#if defined(__GNUC__)
      // The next lookup's slot, most likely: its bookkeeping line is written then, and is cold (a role's work
      // in between touches other memory). A hint only: a wrong guess costs one load.
      if (m_slotCursor < m_lastSlotOrder.size()) __builtin_prefetch(m_lastSlotOrder[m_slotCursor].slot, 1);
#endif
      return *slot;
    }
  } else {
    std::unique_ptr<AnchorSlot>& owned = m_anchorSlots[key];
    if (!owned) owned = std::make_unique<AnchorSlot>();
    slot = owned.get();
  }
  if (slot->lastStep + 1 >= m_stepCounter && slot->order < m_lastSlotOrder.size() &&
      m_lastSlotOrder[slot->order].slot == slot) {
    m_slotCursor = slot->order + 1;  // found where last step's walk had it: go on from there
  }
  if (slot->shellObject != shell || slot->fieldObject != field || slot->lastStep + 1 < m_stepCounter) {
    slot->table.clear();  // another pair reuses the manifold, or the pair was not dispatched (asleep)
    slot->coherence.reset();
    slot->shellObject = shell;
    slot->fieldObject = field;
  }
  if (slot->lastStep != m_stepCounter) {  // this step's walk, for the next step's guesses
    slot->lastStep = m_stepCounter;
    slot->order = m_slotOrder.size();
    recordVisit();
  }
  return *slot;
}

void SdfccdContactSystem::processPair(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                                      const btDispatcherInfo& dispatchInfo, btManifoldResult* resultOut,
                                      btPersistentManifold* manifold, SdfccdSolverPair* solverPair,
                                      bool closestPointsOnly) {
  // The step's first pair plans the step: every pair of ours computed at once, on the pool.
  if (!closestPointsOnly && !m_planning && m_plannedStep != m_stepCounter) planStep(dispatchInfo);
  // Neither body moves (sleeping, static, kinematic at rest): no CCD, and the manifold keeps its points.
  if (!closestPointsOnly && detail::pairAtRest(*wrap0->getCollisionObject(), *wrap1->getCollisionObject())) {
    if (!m_planning) ++m_stats.restingPairs;
    return;
  }
  const btCollisionShape* shape0 = wrap0->getCollisionShape();
  const btCollisionShape* shape1 = wrap1->getCollisionShape();
  const ShapeKind kind0 = detail::shapeKind(shape0);
  const ShapeKind kind1 = detail::shapeKind(shape1);
  const bool ours0 = kind0 == ShapeKind::Ours;
  const bool ours1 = kind1 == ShapeKind::Ours;
  const ShapeKind otherKind = ours0 ? kind1 : kind0;
  // Solver mode keeps its points across steps (solver_manifolds.cpp); penalty mode reports afresh each step.
  const bool solver = m_settings.mode == SdfccdContactMode::Solver && !closestPointsOnly && solverPair != nullptr;
  if (!solver && !m_planning) {
    manifold->clearManifold();
    if (!closestPointsOnly) manifold->setContactProcessingThreshold(-BT_LARGE_FLOAT);
  }
  if (!m_planning) resultOut->setPersistentManifold(manifold);
  // A pair computed in this step's parallel batch (every role of it: our shells against our fields or a plane)
  // applies its roles' results in role order, with no second setup (sdfccd_parallel_step.cpp).
  if (!m_planning && !closestPointsOnly && m_deferred->pending(manifold, 0) &&
      std::find(m_planIncomplete.begin(), m_planIncomplete.end(), manifold) == m_planIncomplete.end()) {
    applyPlannedPair(wrap0, wrap1, dispatchInfo, resultOut, manifold, solver ? solverPair : nullptr);
    return;
  }
  // Unsupported: no shape of ours (btSdfCollisionShape shares our type id), a shape we cannot read, or a convex
  // shape without volume (its shell or field would be null).
  const bool convexOk = otherKind != ShapeKind::Convex ||
                        m_convexShapes->field(static_cast<const btConvexShape*>(ours0 ? shape1 : shape0)) != nullptr;
  if (!(ours0 || ours1) || otherKind == ShapeKind::Unsupported || !convexOk) {
    reportUnsupported(shape0, shape1);
    return;
  }
  const double timeStep = dispatchInfo.m_timeStep > 0 ? double(dispatchInfo.m_timeStep) : 1.0 / 60.0;
  // Closest-point queries use fresh, local body states (poses now, nothing moves).
  std::vector<BodyStep> savedBodies;
  std::unordered_map<const btCollisionObject*, std::size_t> savedIndex;
  if (closestPointsOnly) {
    savedBodies.swap(m_bodies);
    savedIndex.swap(m_bodyIndex);
  }
  const std::size_t index0 =
      static_cast<std::size_t>(&bodyStep(wrap0, timeStep, !closestPointsOnly && !solver) - m_bodies.data());
  const std::size_t index1 =
      static_cast<std::size_t>(&bodyStep(wrap1, timeStep, !closestPointsOnly && !solver) - m_bodies.data());
  // A body with a non-finite state (set by the user; Bullet integrates whatever it is given) takes part in
  // no contact: its impulses would carry the NaN into the other body.
  if (!m_bodies[index0].finiteState || !m_bodies[index1].finiteState) {
    if (!m_planning) ++m_stats.nonFinitePairs;
    if (closestPointsOnly) {
      m_bodies.swap(savedBodies);
      m_bodyIndex.swap(savedIndex);
    }
    return;
  }

  // Which wrapper is the manifold's body 0 (Bullet may hand a pair over in either order).
  const bool swapped = manifold->getBody0() != wrap0->getCollisionObject();
  if (solver) {
    m_candidates.clear();
    m_candidateBounce.clear();
    m_candidateDistance.clear();
    m_candidateMargin = 0.0;
    m_solverTimeStep = timeStep;
  }
  // Penalty mode runs the role's penalty integrals, solver mode collects its candidates.
  auto respond = [&](const Role& role, const auto& field, double cellSize) {
    if (solver) {
      collectSolverCandidates(role, field, cellSize, role.shellIsBody0 != swapped);
    } else {
      processRole(role, field, m_settings.toiDepthCells, cellSize, timeStep, resultOut, closestPointsOnly);
    }
  };

  // One role: the shell of `shellWrap` (ours, or a convex's surface points) against the field of `fieldWrap`
  // (ours, or a plane's or a convex's analytic field).
  // The pair's material, combined the Bullet way (contact_material.h), unless the settings override it.
  const btCollisionObject* object0 = wrap0->getCollisionObject();
  const btCollisionObject* object1 = wrap1->getCollisionObject();
  // Per-body overrides (setBodyContact) combined; without any, the world's settings themselves (no copy per pair).
  std::optional<PenaltySettings> combined;
  if (!m_bodyContacts.empty()) combined = combinedPenalty(object0, object1);
  const PenaltySettings& penalty = combined ? *combined : m_settings.penalty;
  const double friction =
      penalty.frictionFromBodies ? double(gCalculateCombinedFrictionCallback(object0, object1)) : penalty.friction;
  double dampingRatio = penalty.dampingRatio;
  if (penalty.dampingRatioFromRestitution) {
    const double e = double(gCalculateCombinedRestitutionCallback(object0, object1));
    dampingRatio = dampingRatioFromRestitution(std::clamp(e, 0.0, 1.0));
  }
  const bool convexOther = otherKind == ShapeKind::AnalyticConvex || otherKind == ShapeKind::Convex;
  const bool bothRoles = (ours0 && ours1) || convexOther;
  int roleIndex = 0;
  auto runRole = [&](std::size_t shell, std::size_t field, const btCollisionObjectWrapper* shellWrap,
                     const btCollisionObjectWrapper* fieldWrap, bool shellIsBody0) {
    Role role;
    role.shell = shell;
    role.field = field;
    role.shellIsBody0 = shellIsBody0;
    role.bodyFromShellChild = detail::bodyFromChild(*shellWrap);
    role.bodyFromFieldChild = detail::bodyFromChild(*fieldWrap);
    role.roleScale = bothRoles ? 0.5 : 1.0;
    role.friction = std::clamp(friction, 0.0, kMaxCombinedFriction);
    role.dampingRatio = dampingRatio;
    role.penalty = &penalty;
    role.manifold = manifold;
    role.index = roleIndex;
    const btCollisionShape* shellShape = shellWrap->getCollisionShape();
    const btCollisionShape* fieldShape = fieldWrap->getCollisionShape();
    const bool shellOurs = (shellWrap == wrap0 ? kind0 : kind1) == ShapeKind::Ours;
    const ShapeKind fieldKind = fieldWrap == wrap0 ? kind0 : kind1;
    const bool fieldOurs = fieldKind == ShapeKind::Ours;
    const bool anchors = !closestPointsOnly && penalty.enableFriction && penalty.frictionModel == FrictionModel::Anchor;
    // The CCD history only for our shell tree against our grid field (both persistent, owned by the shapes'
    // BodyModels, and keyed by instance id) or the analytic plane and box (keyed by their values). Other shells
    // and fields are per-step objects: no history.
    const bool coherent =
        !closestPointsOnly && m_settings.coherentCcd && shellOurs &&
        (fieldOurs || fieldKind == ShapeKind::Plane || fieldShape->getShapeType() == BOX_SHAPE_PROXYTYPE);
    if (anchors || coherent) {  // one map lookup per role (a pile has thousands of slots)
      // anchorSlot() keeps the slot: it forgets table and history when another pair reuses the manifold.
      AnchorSlot& slot =
          anchorSlot(manifold, roleIndex, shellWrap->getCollisionObject(), fieldWrap->getCollisionObject());
      if (anchors) role.anchors = &slot.table;
      if (coherent) role.coherence = &slot.coherence;
    }
    ++roleIndex;
    // Our shell against our field or a plane may run in the step's parallel batch (deferred_queries.h).
    role.deferrable = !closestPointsOnly && shellOurs && (fieldOurs || fieldKind == ShapeKind::Plane);
    if (fieldOurs) {
      const BodyModel& fieldModel = static_cast<const SdfccdShape*>(fieldShape)->model();
      role.bodyFromField = fieldModel.bodyFromField();
      role.modelBodyFromField = &fieldModel.bodyFromField();
      if (shellOurs) {
        role.shellTree = &static_cast<const SdfccdShape*>(shellShape)->model().tree();
      } else {
        role.shellTree = (shellWrap == wrap0 ? kind0 : kind1) == ShapeKind::Mesh
                             ? meshVertexTree(role, shellShape, fieldShape)
                             : otherShellTree(shellShape, fieldModel.cellSize());
        if (role.shellTree == nullptr) return;
      }
      respond(role, fieldModel.field(), fieldModel.cellSize());
      return;
    }
    // An analytic field: depths are reported in cells of the shell body's own field.
    const BodyModel& shellModel = static_cast<const SdfccdShape*>(shellShape)->model();
    role.shellTree = &shellModel.tree();
    const double shellCell = shellModel.cellSize();
    if (fieldKind == ShapeKind::Plane) {
      const auto* plane = static_cast<const btStaticPlaneShape*>(fieldShape);
      const PlaneField planeField(toVec3(plane->getPlaneNormal()), double(plane->getPlaneConstant()));
      respond(role, planeField, shellCell);
    } else if (fieldKind == ShapeKind::AnalyticConvex) {
      withConvexField(fieldShape, [&](const auto& convexField) { respond(role, convexField, shellCell); });
    } else if (fieldKind == ShapeKind::Convex) {  // a cylinder's or cone's exact field, or the hull's
      if (const std::optional<RevolvedConvexField> revolved = detail::revolvedField(fieldShape)) {
        respond(role, *revolved, shellCell);
      } else {
        respond(role, *m_convexShapes->field(static_cast<const btConvexShape*>(fieldShape)), shellCell);
      }
    } else {  // a triangle mesh or terrain: the triangles near the shell's motion
      // The field sits the mesh's margin off its triangles (meshTrianglesInBox): gather that much further too.
      const double reach = std::max({m_settings.penalty.sigma, m_settings.maxSpeculativeMargin, 0.0}) + shellCell +
                           double(fieldShape->getMargin());
      const std::optional<TriangleSetField> mesh = meshFieldNear(role, shellShape, fieldShape, reach);
      if (mesh) respond(role, *mesh, shellCell);
    }
  };
  // Every body with a shell takes the shell role once: ours always; a convex only against our field.
  if (ours0 || ours1)
    runRole(ours0 ? index0 : index1, ours0 ? index1 : index0, ours0 ? wrap0 : wrap1, ours0 ? wrap1 : wrap0, ours0);
  if (ours0 && ours1) {
    runRole(index1, index0, wrap1, wrap0, false);
  } else if (convexOther || otherKind == ShapeKind::Mesh) {  // a mesh's vertices: at full strength (roleScale)
    runRole(ours0 ? index1 : index0, ours0 ? index0 : index1, ours0 ? wrap1 : wrap0, ours0 ? wrap0 : wrap1, !ours0);
  }
  if (solver && !m_planning)
    writeSolverManifolds(swapped ? wrap1 : wrap0, swapped ? wrap0 : wrap1, manifold, *solverPair);

  if (closestPointsOnly) {
    m_bodies.swap(savedBodies);
    m_bodyIndex.swap(savedIndex);
  }
}

template <class Field>
void SdfccdContactSystem::processRole(const Role& role, const Field& field, double thresholdCells, double cellSize,
                                      double timeStep, btManifoldResult* resultOut, bool closestPointsOnly) {
  constexpr bool ground = std::is_same_v<Field, PlaneField>;
  // Computed in this step's parallel batch: apply it.
  if (const detail::RoleResult* planned = takePlanned(role, detail::kDeferrableField<Field>)) {
    applyPenaltyRole(*planned, resultOut, closestPointsOnly);
    return;
  }
  // What the role's input is built from. A planned role keeps pointers to what stays put through the step only:
  // the bodies' motions (m_bodies is not resized during the batch: planStep reserves it), the models' frames, the
  // world's settings, and copies in the batch's slots of what is the role's own.
  detail::PenaltyRoleFacts<BodyStep> facts;
  facts.shell = &m_bodies[role.shell];
  facts.fieldBody = &m_bodies[role.field];
  facts.bodyFromShellChild = &role.bodyFromShellChild;
  facts.bodyFromFieldChild = &role.bodyFromFieldChild;
  facts.bodyFromField = &role.bodyFromField;
  facts.penalty = role.penalty != nullptr ? role.penalty : &m_settings.penalty;
  facts.anchors = role.anchors;
  facts.coherence = role.coherence;
  facts.shellIndex = role.shell;
  facts.fieldIndex = role.field;
  facts.timeStep = timeStep;
  facts.cellSize = cellSize;
  facts.thresholdCells = thresholdCells;
  facts.roleScale = role.roleScale;
  facts.friction = role.friction;
  facts.dampingRatio = role.dampingRatio;
  facts.octree = m_settings.octree;
  facts.maxManifoldPoints = m_settings.maxManifoldPoints;
  facts.useTree = m_settings.useTree;
  facts.shellIsBody0 = role.shellIsBody0;
  facts.closestPointsOnly = closestPointsOnly;
  facts.discreteModel = m_settings.penalty.model == PenaltyModel::Discrete;
  facts.timeOfImpactClamp = m_settings.timeOfImpactClamp;
  facts.shadowLinear = !closestPointsOnly && m_settings.shadowLinearEvery > 0 &&
                       m_stepCounter % m_settings.shadowLinearEvery == 0 && !ground;
  facts.cpuClock = m_settings.shadowLinearEvery > 0;
  facts.ground = ground;
  if (m_planning) {
    if constexpr (detail::kDeferrableField<Field>) {
      if (role.deferrable) queuePenaltyRole(role, field, facts);
    }
    return;
  }
  detail::PenaltyRoleInput in;
  detail::fillPenaltyInput(facts, in);
  if (!m_roleScratch) m_roleScratch = std::make_unique<detail::RoleResult>();
  detail::computePenaltyRole(*role.shellTree, field, in, *m_roleScratch);
  applyPenaltyRole(*m_roleScratch, resultOut, closestPointsOnly);
}

template <class Field>
void SdfccdContactSystem::queuePenaltyRole(const Role& role, const Field& field,
                                           const detail::PenaltyRoleFacts<BodyStep>& facts) {
  // Filled in its slot (no copy of a local); what points into `role` (a local of processPair) is made to last.
  using Plan = detail::PenaltyRolePlan<Field, BodyStep>;
  Plan& plan = m_deferred->slot<Plan>();
  plan.tree = role.shellTree;
  plan.field = detail::HeldField<Field>(field);
  plan.facts = facts;
  plan.facts.bodyFromShellChild = lastingFrame(role.bodyFromShellChild, nullptr);
  plan.facts.bodyFromFieldChild = lastingFrame(role.bodyFromFieldChild, nullptr);
  plan.facts.bodyFromField = lastingFrame(role.bodyFromField, role.modelBodyFromField);
  // The bodies' frames, kept for the step's other roles of the same bodies, when the child frames are ones whose
  // value never changes (the identity, the model's field frame; not a stashed copy, whose address may be reused).
  const Rigid* identity = &detail::identityFrame();
  if (plan.facts.bodyFromShellChild == identity) {
    plan.facts.shellFrames = detail::keptShellFrames(m_bodies[role.shell], identity);
  }
  if (plan.facts.bodyFromFieldChild == identity && role.modelBodyFromField != nullptr &&
      plan.facts.bodyFromField == role.modelBodyFromField) {
    plan.facts.fieldFrames = detail::keptFieldFrames(m_bodies[role.field], identity, role.modelBodyFromField);
  }
  // Without per-body overrides the pair's parameters are the world's (combinedPenalty returns them untouched).
  plan.facts.penalty =
      m_bodyContacts.empty() || role.penalty == nullptr ? &m_settings.penalty : &m_deferred->stash(*role.penalty);
  const auto run = [](const void* data, detail::RoleResult& out) {
    const Plan& p = *static_cast<const Plan*>(data);
    // One input per thread, reused: fillPenaltyInput writes the same fields for every role, unconditionally, and
    // nothing else writes any, so the rest keep their defaults as in a fresh one; building a fresh one per role
    // (~1.2 KB: four identity frames, the default settings) costs more than refilling this one.
    static thread_local detail::PenaltyRoleInput in;
    detail::fillPenaltyInput(p.facts, in);
    detail::computePenaltyRole(*p.tree, p.field.get(), in, out);
  };
  // A refused query (the batch full: not with two roles per planned pair) is computed when Bullet reaches it; its
  // pair is then not applied as a whole (processPair's fast path).
  if (!m_deferred->add(role.manifold, role.index, run, &plan)) m_planIncomplete.push_back(role.manifold);
}

const Rigid* SdfccdContactSystem::lastingFrame(const Rigid& frame, const Rigid* kept) {
  const Rigid& identity = detail::identityFrame();
  if (kept != nullptr) return kept;
  // Bit for bit: the job then computes with exactly these values.
  if (std::memcmp(frame.data(), identity.data(), sizeof(double) * 16) == 0) return &identity;
  return &m_deferred->stash(frame);
}

void SdfccdContactSystem::applyPenaltyRole(const detail::RoleResult& result, btManifoldResult* resultOut,
                                           bool closestPointsOnly) {
  const detail::RoleResult::PenaltySummary& summary = result.penalty;  // the query stayed on its thread
  m_stats.shadowLinearSeconds += result.shadowSeconds;
  m_stats.ccdSeconds += summary.ccdSeconds;
  if (result.ground) {
    m_stats.groundCcdSeconds += summary.ccdSeconds;
    ++m_stats.groundCcdQueries;
  }
  if (summary.coefficients.stiffnessCapped) ++m_stats.softenedPairs;
  ++m_stats.ccdQueries;
  m_stats.segmentQueries += summary.segmentQueries;
  if (!summary.touched) return;
  for (const detail::RoleResult::ManifoldPoint& p : result.manifoldPoints) {
    resultOut->addContactPoint(toBt(p.normal), toBt(p.point), btScalar(p.depth));
  }
  if (closestPointsOnly || !result.hasRecord) return;
  m_records.push_back(result.record);  // one copy, into its place
  Record& record = m_records.back();
  m_stats.penaltySeconds += summary.penaltySeconds;
  m_stats.penaltySamples += record.penalty.samples;
  m_stats.dampingEvaluations += record.penalty.dampingEvaluations;
  m_stats.torqueEvaluations += record.penalty.torqueEvaluations;
  m_stats.frictionEvaluations += record.penalty.frictionEvaluations;
  addContactLoad(record, result.roleScale, summary.coefficients);
  // A kinematic pair keeps its penalty impulses (it is never rewound).
  if (m_settings.forceTiming == ForceTiming::SameStep &&
      (!record.clamp || record.action == ClampAction::KinematicPush)) {
    applyPenaltyImpulses(record);
    record.applied = true;
  }
}

// registerSdfccdAlgorithms(): sdfccd_registration.cpp.

}  // namespace sdfccd