/// @file
/// @brief SdfccdContactSystem's response, after integrateTransforms (Section 4.1 and 5; see
/// sdfccd_contact_system.h): time-of-impact clamping, the inelastic impact at the clamped points, the penalty
/// impulses and the step's contact report.
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <algorithm>
#include <vector>

#include "bullet_conversions.h"
#include "contact_step.h"
#include "sdfccd/bullet/sdfccd_contact_system.h"
#include "sdfccd/response/time_of_impact_clamp.h"

namespace sdfccd {
namespace {
/// Steps between two walks over the anchor slots that drop the stale ones.
constexpr std::int64_t kSlotEvictionPeriod = 64;
}  // namespace

using detail::interpolatePose;
using detail::kImpactIterations;
using detail::toBt;
using detail::toMat3;
using detail::toVec3;

ImpactBody SdfccdContactSystem::impactBody(const BodyStep& b) {
  ImpactBody out;
  if (b.body != nullptr) {
    out.inverseMass = double(b.body->getInvMass());
    out.inverseInertiaInWorld = toMat3(b.body->getInvInertiaTensorWorld());
    out.centerOfMass = toVec3(b.body->getCenterOfMassPosition());
    out.linearVelocity = toVec3(b.body->getLinearVelocity());
    out.angularVelocity = toVec3(b.body->getAngularVelocity());
  } else if (b.kinematic) {
    out.centerOfMass = b.worldFromBodyStart.translation();
    out.linearVelocity = b.velocity.linearStart;
    out.angularVelocity = b.velocity.angularStart;
  }
  return out;
}

void SdfccdContactSystem::setVelocities(const BodyStep& b, const ImpactBody& impact) {
  if (b.body == nullptr) return;
  b.body->setLinearVelocity(toBt(impact.linearVelocity));
  b.body->setAngularVelocity(toBt(impact.angularVelocity));
}

void SdfccdContactSystem::applyContactMass(BodyStep& step, double timeStep) const {
  // Contact mass scaling (per-area law; docs/design/contact-response.md): a body whose contacts' stiffness or damping,
  // summed over all its pairs, exceed what an explicit step carries with its mass m (omega dt <= Omega_max,
  // C dt / m <= maxDampingDt, the caps of contact_material.h taken per body) moves, while in contact, as if it had
  // the mass m_c that brings it back within them: its penalty impulses J and its external forces F act as
  // Delta v = (J + F dt) / m_c. The light box under a heavy one feels both its contacts at once, which no per-pair
  // cap sees (with the per-pair caps alone it drifts 165 mm and sinks 2.1 cells deep); with m_c it rests 0.65
  // cell deep and still. Scaling F with J keeps rest exact (J = -F dt, whatever m_c); only the body's response
  // to a change of load is slower. The load is last step's (contacts persist; a first contact has the per-pair
  // caps alone).
  if (step.body == nullptr || !(step.mass.inverseMass > 0.0)) return;
  const auto found = m_contactLoads.find(step.object);
  if (found == m_contactLoads.end()) return;
  const StabilityCapSettings& caps = m_settings.penalty.caps;
  const double mass = 1.0 / step.mass.inverseMass;
  const double stepPerOmega = timeStep / caps.maxOmegaDt;
  const double contactMass = std::max({mass, found->second.stiffness * stepPerOmega * stepPerOmega,
                                       found->second.damping * timeStep / caps.maxDampingDt});
  if (!(contactMass > mass)) return;
  step.contactMassScale = mass / contactMass;
  step.mass.inverseMass *= step.contactMassScale;
  step.mass.inverseInertiaInWorld *= step.contactMassScale;
  // Bullet integrates F dt / m in full: take back the share (1 - m / m_c) of it.
  const btScalar share = btScalar(step.contactMassScale - 1.0) * btScalar(timeStep);
  step.body->applyCentralImpulse(step.body->getTotalForce() * share);
  step.body->applyTorqueImpulse(step.body->getTotalTorque() * share);
}

void SdfccdContactSystem::addContactLoad(const Record& record, double roleScale, const PairResponseCoefficients& c) {
  if (!(c.stiffnessScale > 0.0) || !(c.totalStiffness > 0.0)) return;
  const double stiffness = roleScale * c.totalStiffness / c.stiffnessScale;  // this role's share, before the cap
  const double damping = roleScale * c.totalDamping;
  const BodyStep& shell = m_bodies[record.shell];
  const BodyStep& field = m_bodies[record.field];
  // A pair of two dynamic bodies counts twice (a Gershgorin bound of the coupled bodies' stiffness).
  const double coupling = shell.body != nullptr && field.body != nullptr ? 2.0 : 1.0;
  for (const BodyStep* b : {&shell, &field}) {
    if (b->body == nullptr) continue;
    ContactLoad& load = m_nextContactLoads[b->object];
    load.stiffness += coupling * stiffness;
    load.damping += damping;
  }
}

void SdfccdContactSystem::applyPenaltyImpulses(const Record& r) {
  for (int side = 0; side < 2; ++side) {
    const BodyStep& step = m_bodies[side == 0 ? r.shell : r.field];
    btRigidBody* body = step.body;
    if (body == nullptr) continue;
    // Contact mass scaling (applyContactMass): the body takes J m / m_c.
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

void SdfccdContactSystem::updateAction(btCollisionWorld*, btScalar) {
  if (m_settings.shadowLinearEvery > 0 && m_stepCounter % m_settings.shadowLinearEvery == 0) ++m_stats.shadowSteps;
  ++m_stepCounter;
  m_lastContacts.clear();
  m_lastContactCount = 0;
  m_lastMaxPenetrationCells = 0.0;
  m_lastClamps = 0;

  // 1. Time-of-impact clamping: each dynamic body goes back to its earliest clamp fraction (pairs with a
  //    kinematic body are never rewound: time_of_impact_clamp.h).
  for (const Record& r : m_records) {
    if (!r.clamp || r.action != ClampAction::Rewind) continue;
    for (std::size_t side : {r.shell, r.field}) {
      BodyStep& b = m_bodies[side];
      if (b.body != nullptr) b.clampFraction = std::min(b.clampFraction, r.clampFraction);
    }
  }
  for (BodyStep& b : m_bodies) {
    if (b.body == nullptr || !(b.clampFraction < 1.0)) continue;
    b.clamped = true;
    b.body->setCenterOfMassTransform(toBt(interpolatePose(b.worldFromBodyStart, b.worldFromBodyEnd, b.clampFraction)));
    ++m_lastClamps;
    ++m_stats.clamps;
  }
  // 2. Inelastic impact at the entering points (core: resolveInelasticImpact), with a kinematic body's own
  //    velocity; then a dynamic body hit by a kinematic one follows what the kinematic advanced after the hit.
  for (const Record& r : m_records) {
    if (!r.clamp) continue;
    ImpactBody shell = impactBody(m_bodies[r.shell]);
    ImpactBody field = impactBody(m_bodies[r.field]);
    std::vector<ImpactPoint> points;
    points.reserve(r.clampPoints.size());
    for (const Record::ClampPoint& p : r.clampPoints) points.push_back(ImpactPoint{p.point, p.normal});
    resolveInelasticImpact(points, shell, field, kImpactIterations);
    setVelocities(m_bodies[r.shell], shell);
    setVelocities(m_bodies[r.field], field);
    if (r.action != ClampAction::KinematicPush || r.clampPoints.empty()) continue;
    ++m_stats.kinematicPushes;
    const bool shellMoves = m_bodies[r.field].kinematic;
    const BodyStep& kinematic = m_bodies[shellMoves ? r.field : r.shell];
    BodyStep& moved = m_bodies[shellMoves ? r.shell : r.field];
    if (moved.body == nullptr) continue;
    const Vec3 normal = shellMoves ? r.clampPoints.front().normal : Vec3(-r.clampPoints.front().normal);
    const Vec3 push = kinematicPushDistance(kinematic.velocity.linearStart, normal, r.clampFraction, r.timeStep);
    if (push.isZero(0.0)) continue;
    btTransform pose = moved.body->getCenterOfMassTransform();
    pose.setOrigin(pose.getOrigin() + toBt(push));
    moved.body->setCenterOfMassTransform(pose);
  }
  // 3. NextStep timing: penalty impulses (eq. 5: F* dt) of the pairs whose bodies were not moved back.
  for (const Record& r : m_records) {
    const bool rewound =
        (r.clamp && r.action == ClampAction::Rewind) || m_bodies[r.shell].clamped || m_bodies[r.field].clamped;
    const bool skip = r.applied || rewound;
    if (!skip) applyPenaltyImpulses(r);
    SdfccdPairContact report;
    report.shellObject = m_bodies[r.shell].object;
    report.fieldObject = m_bodies[r.field].object;
    report.contactCount = r.penalty.contactCount;
    report.maxPenetration = r.penalty.maxPenetration;
    report.maxPenetrationCells = r.maxPenetrationCells;
    report.forceOnShell = r.penalty.forceOnShell;
    report.torqueOnShell = r.penalty.torqueOnShell;
    report.forceOnField = r.penalty.forceOnField;
    report.torqueOnField = r.penalty.torqueOnField;
    report.clamped = r.clamp;
    report.firstFraction = r.firstFraction;
    m_lastContacts.push_back(report);
    m_lastContactCount += r.penalty.contactCount;
    m_lastMaxPenetrationCells = std::max(m_lastMaxPenetrationCells, r.maxPenetrationCells);
  }
  m_stats.maxPenetrationCells = std::max(m_stats.maxPenetrationCells, m_lastMaxPenetrationCells);
  // This step's walk of the slots guides the next step's lookups (anchorSlot).
  m_lastSlotOrder.swap(m_slotOrder);
  m_slotOrder.clear();
  m_slotCursor = 0;
  // Slots whose pair was not processed last step are dropped now and then: one that comes back first resets
  // (anchorSlot), so when they go changes no result, and walking every slot each step costs as much as a query.
  if (m_stepCounter % kSlotEvictionPeriod == 0) {
    for (auto it = m_anchorSlots.begin(); it != m_anchorSlots.end();) {
      it = it->second->lastStep + 1 < m_stepCounter ? m_anchorSlots.erase(it) : std::next(it);
    }
  }
  m_records.clear();
  // The entries stay (zeroed), so next step adds to them without allocating; a body with a zero load gets its own
  // mass (applyContactMass), as one without an entry.
  m_contactLoads.swap(m_nextContactLoads);
  if (m_nextContactLoads.size() > 2 * m_bodies.size() + 256) m_nextContactLoads.clear();  // bodies come and go
  for (auto& entry : m_nextContactLoads) entry.second = ContactLoad{};
  m_bodies.clear();
  m_bodyIndex.clear();
}

}  // namespace sdfccd
