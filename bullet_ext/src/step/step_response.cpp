/// @file
/// @brief ContactStep's response, after integrateTransforms (Section 4.1 and 5; see contact_system.h): time-of-impact
/// clamping, the impact at the clamped points (the pair's restitution), the penalty impulses and the step's contact report.
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <algorithm>
#include <vector>

#include "common/bullet_conversions.h"
#include "sdfccd/response/time_of_impact_clamp.h"
#include "step/contact_step.h"

namespace sdfccd::bullet::detail {
namespace {

ImpactBody impactBody(const BodyStep& b) {
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

void setVelocities(const BodyStep& b, const ImpactBody& impact) {
  if (b.body == nullptr) return;
  b.body->setLinearVelocity(toBt(impact.linearVelocity));
  b.body->setAngularVelocity(toBt(impact.angularVelocity));
}

}  // namespace

void ContactStep::updateAction(btCollisionWorld*, btScalar) {
  if (m_data.shadowStep()) ++m_data.stats.shadowSteps;
  ++m_data.stepCounter;
  m_lastContacts.clear();
  m_lastContactCount = 0;
  m_lastMaxPenetrationCells = 0.0;
  m_lastClamps = 0;
  clampAndImpact();
  applyAndReport();
  m_data.stats.maxPenetrationCells = std::max(m_data.stats.maxPenetrationCells, m_lastMaxPenetrationCells);
  m_slots.endStep(m_data.stepCounter);
  m_data.records.clear();
  m_data.loads.endStep(m_data.bodies.size());
  m_data.bodies.clear();
}

void ContactStep::clampAndImpact() {
  const std::vector<ContactRecord>& records = m_data.records;
  BodySteps& bodies = m_data.bodies;
  ContactStatistics& stats = m_data.stats;
  // 1. Time-of-impact clamping: each dynamic body goes back to its earliest clamp fraction (pairs with a
  //    kinematic body are never rewound: time_of_impact_clamp.h).
  for (const ContactRecord& r : records) {
    if (!r.clamp || r.action != ClampAction::Rewind) continue;
    for (std::size_t side : {r.shell, r.field}) {
      BodyStep& b = bodies[side];
      if (b.body != nullptr) b.clampFraction = std::min(b.clampFraction, r.clampFraction);
    }
  }
  for (BodyStep& b : bodies.all()) {
    if (b.body == nullptr || !(b.clampFraction < 1.0)) continue;
    b.clamped = true;
    b.body->setCenterOfMassTransform(toBt(interpolatePose(b.worldFromBodyStart, b.worldFromBodyEnd, b.clampFraction)));
    ++m_lastClamps;
    ++stats.clamps;
  }
  // 2. The impact at the entering points, with the pair's restitution (core: resolveImpact), a kinematic body's own
  //    velocity; then a dynamic body hit by a kinematic one follows what the kinematic advanced after the hit.
  for (const ContactRecord& r : records) {
    if (!r.clamp) continue;
    ImpactBody shell = impactBody(bodies[r.shell]);
    ImpactBody field = impactBody(bodies[r.field]);
    std::vector<ImpactPoint> points;
    points.reserve(r.clampPoints.size());
    for (const ContactRecord::ClampPoint& p : r.clampPoints) points.push_back(ImpactPoint{p.point, p.normal});
    const double restitution =
        double(gCalculateCombinedRestitutionCallback(bodies[r.shell].object, bodies[r.field].object));
    resolveImpact(points, shell, field, restitution, kImpactIterations);
    setVelocities(bodies[r.shell], shell);
    setVelocities(bodies[r.field], field);
    if (r.action != ClampAction::KinematicPush || r.clampPoints.empty()) continue;
    ++stats.kinematicPushes;
    const bool shellMoves = bodies[r.field].kinematic;
    const BodyStep& kinematic = bodies[shellMoves ? r.field : r.shell];
    BodyStep& moved = bodies[shellMoves ? r.shell : r.field];
    if (moved.body == nullptr) continue;
    const Vec3 normal = shellMoves ? r.clampPoints.front().normal : Vec3(-r.clampPoints.front().normal);
    const Vec3 push = kinematicPushDistance(kinematic.velocity.linearStart, normal, r.clampFraction, r.timeStep);
    if (push.isZero(0.0)) continue;
    btTransform pose = moved.body->getCenterOfMassTransform();
    pose.setOrigin(pose.getOrigin() + toBt(push));
    moved.body->setCenterOfMassTransform(pose);
  }
}

void ContactStep::applyAndReport() {
  const BodySteps& bodies = m_data.bodies;
  // 3. NextStep timing: penalty impulses (eq. 5: F* dt) of the pairs whose bodies were not moved back.
  for (const ContactRecord& r : m_data.records) {
    const bool rewound =
        (r.clamp && r.action == ClampAction::Rewind) || bodies[r.shell].clamped || bodies[r.field].clamped;
    const bool skip = r.applied || rewound;
    if (!skip) applyPenaltyImpulses(r, bodies);
    PairContact report;
    report.shellObject = bodies[r.shell].object;
    report.fieldObject = bodies[r.field].object;
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
}

}  // namespace sdfccd::bullet::detail
