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

namespace sdfccd {

using detail::interpolatePose;
using detail::kImpactIterations;
using detail::toBt;

void SdfccdContactSystem::applyPenaltyImpulses(const Record& r) {
  for (int side = 0; side < 2; ++side) {
    btRigidBody* body = m_bodies[side == 0 ? r.shell : r.field].body;
    if (body == nullptr) continue;
    const Vec3& impulse = side == 0 ? r.penalty.impulseOnShell : r.penalty.impulseOnField;
    const Vec3& angular = side == 0 ? r.penalty.angularImpulseOnShell : r.penalty.angularImpulseOnField;
    if (impulse.isZero(0.0) && angular.isZero(0.0)) continue;
    if (!impulse.allFinite() || !angular.allFinite()) continue;  // never spread a NaN (see nonFinitePairs)
    body->applyCentralImpulse(toBt(impulse));
    if (!angular.isZero(0.0)) body->applyTorqueImpulse(toBt(angular));
    if (body->getActivationState() == ISLAND_SLEEPING) body->activate();
  }
}

void SdfccdContactSystem::updateAction(btCollisionWorld*, btScalar) {
  if (m_settings.shadowLinearEvery > 0 && m_stepCounter % m_settings.shadowLinearEvery == 0) ++m_stats.shadowSteps;
  ++m_stepCounter;
  m_lastContacts.clear();
  m_lastContactCount = 0;
  m_lastMaxPenetrationCells = 0.0;
  m_lastClamps = 0;

  // 1. Time-of-impact clamping: each dynamic body goes back to its earliest clamp fraction.
  for (const Record& r : m_records) {
    if (!r.clamp) continue;
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
  // 2. Inelastic impact: sequential impulses at the entering points remove their approaching normal
  //    velocity (accumulated impulse per point kept >= 0, so a later sweep may only take back what it gave).
  for (const Record& r : m_records) {
    if (!r.clamp) continue;
    btRigidBody* shell = m_bodies[r.shell].body;
    btRigidBody* fieldBody = m_bodies[r.field].body;
    // The points moved with the bodies to the clamp fraction; rebuild them from the shell's pose there.
    std::vector<btScalar> accumulated(r.clampPoints.size(), btScalar(0));
    for (int sweep = 0; sweep < kImpactIterations; ++sweep) {
      for (std::size_t k = 0; k < r.clampPoints.size(); ++k) {
        const btVector3 normal = toBt(r.clampPoints[k].normal);  // the shell may move along +normal
        const btVector3 point = toBt(r.clampPoints[k].point);
        btVector3 relativeVelocity(0, 0, 0);
        btScalar denominator = 0;
        btVector3 shellArm(0, 0, 0), fieldArm(0, 0, 0);
        if (shell != nullptr) {
          shellArm = point - shell->getCenterOfMassPosition();
          relativeVelocity += shell->getVelocityInLocalPoint(shellArm);
          denominator += shell->computeImpulseDenominator(point, normal);
        }
        if (fieldBody != nullptr) {
          fieldArm = point - fieldBody->getCenterOfMassPosition();
          relativeVelocity -= fieldBody->getVelocityInLocalPoint(fieldArm);
          denominator += fieldBody->computeImpulseDenominator(point, normal);
        }
        if (!(denominator > 0)) continue;
        const btScalar approach = relativeVelocity.dot(normal);
        const btScalar next = std::max(btScalar(0), accumulated[k] - approach / denominator);
        const btVector3 impulse = normal * (next - accumulated[k]);
        accumulated[k] = next;
        if (shell != nullptr) shell->applyImpulse(impulse, shellArm);
        if (fieldBody != nullptr) fieldBody->applyImpulse(-impulse, fieldArm);
      }
    }
    for (btRigidBody* body : {shell, fieldBody}) {
      if (body != nullptr && body->getActivationState() == ISLAND_SLEEPING) body->activate();
    }
  }
  // 3. NextStep timing: penalty impulses (eq. 5: F* dt) of the pairs whose bodies were not moved back.
  for (const Record& r : m_records) {
    const bool skip = r.applied || r.clamp || m_bodies[r.shell].clamped || m_bodies[r.field].clamped;
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
  m_records.clear();
  m_bodies.clear();
  m_bodyIndex.clear();
}

}  // namespace sdfccd
