/// @file
/// @brief BodySteps (see body_steps.h).
#include "step/body_steps.h"

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>

#include "step/contact_loads.h"
#include "step/motion_prediction.h"

namespace sdfccd::bullet::detail {

std::size_t BodySteps::indexOf(const btCollisionObjectWrapper* wrap, double timeStep, const ContactLoads* massScaling,
                               const StabilityCapSettings& caps) {
  const btCollisionObject* object = wrap->getCollisionObject();
  // Asked twice per pair (an 80-body pile: ~2,000 times per step): the guess by world index spares most lookups
  // of the map, which stays the one record of which objects have their step (m_bodies holds each object once).
  const int worldIndex = object->getWorldArrayIndex();
  const auto guess = static_cast<std::size_t>(worldIndex);
  if (worldIndex >= 0 && guess < m_guess.size() && m_guess[guess] < m_bodies.size() &&
      m_bodies[m_guess[guess]].object == object) {
    return m_guess[guess];
  }
  const auto found = m_index.find(object);
  if (found != m_index.end()) {
    if (worldIndex >= 0 && guess < m_guess.size()) m_guess[guess] = found->second;
    return found->second;
  }
  const PredictedMotion motion = predictBodyMotion(*object, timeStep);
  BodyStep step;
  step.object = object;
  step.body = motion.dynamicBody;
  step.kinematic = motion.kinematic;
  step.worldFromBodyStart = motion.worldFromBodyStart;
  step.worldFromBodyEnd = motion.worldFromBodyEnd;
  step.velocity = motion.velocity;
  step.mass = motion.mass;
  if (massScaling != nullptr) massScaling->applyContactMass(step, timeStep, caps);
  step.finiteState = step.finite();
  if (worldIndex >= 0) {
    if (guess >= m_guess.size()) m_guess.resize(guess + 1, std::size_t(-1));
    m_guess[guess] = m_bodies.size();
  }
  m_index.emplace(object, m_bodies.size());
  m_bodies.push_back(step);
  return m_bodies.size() - 1;
}

bool BodySteps::pairOf(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1, double timeStep,
                       const ContactLoads* massScaling, const StabilityCapSettings& caps, std::size_t& index0,
                       std::size_t& index1) {
  index0 = indexOf(wrap0, timeStep, massScaling, caps);
  index1 = indexOf(wrap1, timeStep, massScaling, caps);
  return m_bodies[index0].finiteState && m_bodies[index1].finiteState;
}

void BodySteps::clear() {
  m_bodies.clear();
  m_index.clear();
}

BodySteps::FreshScope::FreshScope(BodySteps& steps) : m_steps(steps) {
  m_savedBodies.swap(m_steps.m_bodies);
  m_savedIndex.swap(m_steps.m_index);
}

BodySteps::FreshScope::~FreshScope() {
  m_steps.m_bodies.swap(m_savedBodies);
  m_steps.m_index.swap(m_savedIndex);
}

}  // namespace sdfccd::bullet::detail
