/// @file
/// @brief ContactLoads (see contact_loads.h).
#include "step/contact_loads.h"

#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <algorithm>

#include "step/body_steps.h"
#include "step/contact_record.h"

namespace sdfccd::bullet::detail {

void ContactLoads::applyContactMass(BodyStep& step, double timeStep, const StabilityCapSettings& caps) const {
  // Contact mass scaling (per-area law; docs/design/contact-response.md): a body whose contacts' stiffness or damping,
  // summed over all its pairs, exceed what an explicit step carries with its mass m (omega dt <= Omega_max,
  // C dt / m <= maxDampingDt, the caps of contact_material.h taken per body) moves, while in contact, as if it had
  // the mass m_c that brings it back within them: its penalty impulses J and its external forces F act as
  // Delta v = (J + F dt) / m_c. The light box under a heavy one feels both its contacts at once, which no per-pair
  // cap sees (with the per-pair caps alone it drifts and sinks two cells deep); with m_c it rests under a cell deep
  // and still. Scaling F with J keeps rest exact (J = -F dt, whatever m_c); only the body's response to a change of
  // load is slower. The load is last step's (contacts persist; a first contact has the per-pair caps alone).
  if (step.body == nullptr || !(step.mass.inverseMass > 0.0)) return;
  const auto found = m_loads.find(step.object);
  if (found == m_loads.end()) return;
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

void ContactLoads::add(const ContactRecord& record, double roleScale, const PairResponseCoefficients& c,
                       const BodySteps& bodies) {
  if (!(c.stiffnessScale > 0.0) || !(c.totalStiffness > 0.0)) return;
  const double stiffness = roleScale * c.totalStiffness / c.stiffnessScale;  // this role's share, before the cap
  const double damping = roleScale * c.totalDamping;
  const BodyStep& shell = bodies[record.shell];
  const BodyStep& field = bodies[record.field];
  // A pair of two dynamic bodies counts twice (a Gershgorin bound of the coupled bodies' stiffness).
  const double coupling = shell.body != nullptr && field.body != nullptr ? 2.0 : 1.0;
  for (const BodyStep* b : {&shell, &field}) {
    if (b->body == nullptr) continue;
    Load& load = m_nextLoads[b->object];
    load.stiffness += coupling * stiffness;
    load.damping += damping;
  }
}

void ContactLoads::endStep(std::size_t bodyCount) {
  // The entries stay (zeroed), so next step adds to them without allocating; a body with a zero load gets its own
  // mass (applyContactMass), as one without an entry.
  m_loads.swap(m_nextLoads);
  if (m_nextLoads.size() > 2 * bodyCount + 256) m_nextLoads.clear();  // bodies come and go
  for (auto& entry : m_nextLoads) entry.second = Load{};
}

}  // namespace sdfccd::bullet::detail
