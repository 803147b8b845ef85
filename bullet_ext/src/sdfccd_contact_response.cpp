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

void SdfccdContactSystem::applyPenaltyImpulses(const Record& r) {
  for (int side = 0; side < 2; ++side) {
    btRigidBody* body = m_bodies[side == 0 ? r.shell : r.field].body;
    if (body == nullptr) continue;
    const Vec3& impulse = side == 0 ? r.penalty.impulseOnShell : r.penalty.impulseOnField;
    const Vec3& angular = side == 0 ? r.penalty.angularImpulseOnShell : r.penalty.angularImpulseOnField;
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
  for (auto it = m_anchorSlots.begin(); it != m_anchorSlots.end();) {
    it = it->second->lastStep + 1 < m_stepCounter ? m_anchorSlots.erase(it) : std::next(it);
  }
  m_records.clear();
  m_bodies.clear();
  m_bodyIndex.clear();
}

}  // namespace sdfccd
