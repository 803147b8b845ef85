/// @file
/// @brief ContactSystem (see contact_system.h): what it installs in a world and takes out again, and its reports.
///
/// @details Bullet's dispatcher and world keep raw pointers (the create functions, the action): the ContactSystem
/// owns what they point at, and its lifetime, the program's, decides theirs. Installing: the create functions in
/// every dispatcher entry involving our shape type, the action, the world whose pairs each step plans. Removing,
/// in the destructor: the action, the pair algorithms of the world's pairs (ours point at this system, and so do
/// the child algorithms Bullet's compound algorithms hold), and every entry back to btEmptyAlgorithm.
#include "sdfccd/bullet/contact_system.h"

#include <BulletCollision/BroadphaseCollision/btOverlappingPairCache.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcherMt.h>
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletCollision/CollisionDispatch/btEmptyCollisionAlgorithm.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorldMt.h>
#include <BulletDynamics/Dynamics/btDynamicsWorld.h>

#include "algorithm/collision_algorithm.h"
#include "sdfccd/error.h"
#include "step/contact_step.h"

namespace sdfccd::bullet {
namespace {

/// The dispatcher's create function of (our type, our type) for contacts. Bullet has no getter: the member is
/// protected, and a pointer to it taken through a derived class may be applied to any dispatcher.
const btCollisionAlgorithmCreateFunc* ourPairEntry(const btCollisionDispatcher& dispatcher) {
  struct Peek : btCollisionDispatcher {
    static const btCollisionAlgorithmCreateFunc* entry(const btCollisionDispatcher& d) {
      return (d.*(&Peek::m_doubleDispatchContactPoints))[CUSTOM_CONCAVE_SHAPE_TYPE][CUSTOM_CONCAVE_SHAPE_TYPE];
    }
  };
  return Peek::entry(dispatcher);
}

/// Throws unless `dispatcher` may take a ContactSystem: not the multi-threaded one, and no live ContactSystem
/// (whose entries a second one would overwrite, and whose destruction would then empty them).
btCollisionDispatcher& checkedDispatcher(btDispatcher* dispatcher) {
  auto* plain = dynamic_cast<btCollisionDispatcher*>(dispatcher);
  if (plain == nullptr) throw Error("ContactSystem: the world's dispatcher is not a btCollisionDispatcher");
  if (dynamic_cast<btCollisionDispatcherMt*>(plain) != nullptr) {
    throw Error(
        "ContactSystem: btCollisionDispatcherMt is not supported (the sdfccd narrowphase is single-threaded): use "
        "btCollisionDispatcher");
  }
  if (dynamic_cast<const detail::CollisionAlgorithm::CreateFunc*>(ourPairEntry(*plain)) != nullptr) {
    throw Error("ContactSystem: this btCollisionDispatcher has a live ContactSystem (one per dispatcher)");
  }
  return *plain;
}

/// Frees every pair algorithm of a pair cache (Bullet creates a new one on the pair's next step). Not only ours:
/// Bullet's compound algorithms hold child algorithms of ours.
struct ForgetPairAlgorithms : btOverlapCallback {
  explicit ForgetPairAlgorithms(btDispatcher* dispatcher) : m_dispatcher(dispatcher) {}
  bool processOverlap(btBroadphasePair& pair) override {
    if (pair.m_algorithm != nullptr) {
      pair.m_algorithm->~btCollisionAlgorithm();
      m_dispatcher->freeCollisionAlgorithm(pair.m_algorithm);
      pair.m_algorithm = nullptr;
    }
    return false;  // keep the pair
  }
  btDispatcher* m_dispatcher;
};

}  // namespace

ContactSystem::ContactSystem(btCollisionWorld& world, const ContactSettings& settings) {
  if (dynamic_cast<btDiscreteDynamicsWorldMt*>(&world) != nullptr) {
    throw Error(
        "ContactSystem: btDiscreteDynamicsWorldMt is not supported (the sdfccd narrowphase is single-threaded): use "
        "btDiscreteDynamicsWorld");
  }
  m_dispatcher = &checkedDispatcher(world.getDispatcher());
  m_step = std::make_unique<detail::ContactStep>(settings);
  // Pairs the world has already get their algorithms anew, from our entries.
  ForgetPairAlgorithms forget(m_dispatcher);
  world.getPairCache()->processAllOverlappingPairs(&forget, m_dispatcher);
  m_step->registerWith(*m_dispatcher);
  m_world = &world;
  if (auto* dynamics = dynamic_cast<btDynamicsWorld*>(&world)) {
    dynamics->addAction(m_step.get());
    m_action = true;
    m_step->attachWorld(&world);  // its pairs are planned and computed in parallel (step_planner.h)
  }
}

ContactSystem::ContactSystem(btCollisionDispatcher& dispatcher, const ContactSettings& settings) {
  m_dispatcher = &checkedDispatcher(&dispatcher);
  m_step = std::make_unique<detail::ContactStep>(settings);
  m_step->registerWith(*m_dispatcher);
}

ContactSystem::~ContactSystem() {
  if (m_action) static_cast<btDynamicsWorld*>(m_world)->removeAction(m_step.get());
  m_step->attachWorld(nullptr);
  if (m_world != nullptr) {
    ForgetPairAlgorithms forget(m_dispatcher);
    m_world->getPairCache()->processAllOverlappingPairs(&forget, m_dispatcher);
  }
  // No entry may keep pointing at the step's create functions: btEmptyAlgorithm's (one, never freed). These are
  // the entries registerOurPairs sets (every pair involving our type, both orders, both query types).
  static btEmptyAlgorithm::CreateFunc empty;
  for (int other = 0; other < MAX_BROADPHASE_COLLISION_TYPES; ++other) {
    m_dispatcher->registerCollisionCreateFunc(CUSTOM_CONCAVE_SHAPE_TYPE, other, &empty);
    m_dispatcher->registerCollisionCreateFunc(other, CUSTOM_CONCAVE_SHAPE_TYPE, &empty);
    m_dispatcher->registerClosestPointsCreateFunc(CUSTOM_CONCAVE_SHAPE_TYPE, other, &empty);
    m_dispatcher->registerClosestPointsCreateFunc(other, CUSTOM_CONCAVE_SHAPE_TYPE, &empty);
  }
}

const ContactSettings& ContactSystem::settings() const {
  return m_step->settings();
}

void ContactSystem::setSettings(const ContactSettings& settings) {
  m_step->setSettings(settings);
}

void ContactSystem::setBodyContact(const btCollisionObject* body, const BodyContact& contact) {
  m_step->data().bodyContacts.set(body, contact, m_step->settings().penalty);
}

void ContactSystem::clearBodyContact(const btCollisionObject* body) {
  m_step->data().bodyContacts.clear(body);
}

const BodyContact* ContactSystem::bodyContact(const btCollisionObject* body) const {
  return m_step->data().bodyContacts.find(body);
}

const std::vector<PairContact>& ContactSystem::lastStepContacts() const {
  return m_step->lastContacts();
}

int ContactSystem::lastStepContactCount() const {
  return m_step->lastContactCount();
}

double ContactSystem::lastStepMaxPenetrationCells() const {
  return m_step->lastMaxPenetrationCells();
}

int ContactSystem::lastStepClamps() const {
  return m_step->lastClamps();
}

const ContactStatistics& ContactSystem::statistics() const {
  return m_step->data().stats;
}

void ContactSystem::setLogCallback(LogCallback callback) {
  m_step->setLogCallback(std::move(callback));
}

}  // namespace sdfccd::bullet
