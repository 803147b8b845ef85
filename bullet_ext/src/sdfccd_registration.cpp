/// @file
/// @brief registerSdfccdAlgorithms() and releaseSdfccdAlgorithms() (see sdfccd_contact_system.h): who owns the
/// contact system, and the refusal of Bullet's multi-threaded world and dispatcher.
///
/// @details Bullet's dispatcher and world keep raw pointers (the create functions, the action), and a dispatcher has no
/// slot that would own anything. If the caller owned the system, dropping the returned pointer would be a
/// use-after-free on the first step, so a process-wide table keyed by the dispatcher owns it: the registration, not the
/// caller, decides its lifetime. The entry goes when the same dispatcher is registered again (a new world at the old
/// one's address, or a second registration through the world overload, which frees the pair algorithms first) or when
/// releaseSdfccdAlgorithms() undoes the registration. The dispatcher overload refuses a dispatcher whose registration
/// is still live: it cannot reach the pairs whose algorithms point at the old system.
#include <BulletCollision/BroadphaseCollision/btOverlappingPairCache.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcherMt.h>
#include <BulletCollision/CollisionDispatch/btEmptyCollisionAlgorithm.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorldMt.h>

#include <map>
#include <mutex>

#include "sdfccd/bullet/sdfccd_collision_algorithm.h"
#include "sdfccd/bullet/sdfccd_contact_system.h"
#include "sdfccd/error.h"

namespace sdfccd {

namespace {

struct Registration {
  std::shared_ptr<SdfccdContactSystem> system;
  btDiscreteDynamicsWorld* world = nullptr;  // the world it was added to as an action (the world overload)
  // The dispatcher's entry for our pair just after registering: still there means the registration is live (a
  // new dispatcher at a freed one's address has its configuration's entries instead).
  const btCollisionAlgorithmCreateFunc* ourEntry = nullptr;
};

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

/// The owners of registered systems, by dispatcher.
struct RegistrationTable {
  std::mutex mutex;
  std::map<const btCollisionDispatcher*, Registration> entries;
};

RegistrationTable& registrations() {
  static RegistrationTable table;
  return table;
}

/// Stores `registration` for `dispatcher`, returning the one it replaces (removed from its world by the caller).
Registration store(const btCollisionDispatcher* dispatcher, Registration registration) {
  RegistrationTable& table = registrations();
  const std::lock_guard<std::mutex> lock(table.mutex);
  Registration previous = std::move(table.entries[dispatcher]);
  table.entries[dispatcher] = std::move(registration);
  return previous;
}

/// Frees every pair algorithm of a pair cache (Bullet creates a new one on the pair's next step). Not only ours:
/// Bullet's compound algorithms hold child algorithms of ours, which point at the system being replaced.
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

/// Throws when `dispatcher` holds a live registration: replacing it would free the system under the pair
/// algorithms already created (only the world overload can find and free those first).
void refuseLiveRegistration(const btCollisionDispatcher* dispatcher) {
  RegistrationTable& table = registrations();
  const std::lock_guard<std::mutex> lock(table.mutex);
  const auto found = table.entries.find(dispatcher);
  if (found != table.entries.end() && found->second.ourEntry == ourPairEntry(*dispatcher)) {
    throw Error(
        "registerSdfccdAlgorithms: this btCollisionDispatcher is already registered (register once, or use the "
        "world overload, which replaces the registration)");
  }
}

/// Registers a new system with `dispatcher`, owned by the table; `world` (may be null) gets it as an action.
/// A previous registration of the same dispatcher is released: its world pointer is only trusted when it is
/// `world` itself (else that world may be gone and another lives at its address).
std::shared_ptr<SdfccdContactSystem> registerOwned(btCollisionDispatcher* dispatcher, btDiscreteDynamicsWorld* world,
                                                   const SdfccdContactSettings& settings) {
  if (dynamic_cast<btCollisionDispatcherMt*>(dispatcher) != nullptr) {
    throw Error(
        "registerSdfccdAlgorithms: btCollisionDispatcherMt is not supported (the sdfccd narrowphase is "
        "single-threaded): use btCollisionDispatcher");
  }
  auto system = std::make_shared<SdfccdContactSystem>(settings);
  if (world != nullptr) {
    // A second registration on a live world: the first system's pair algorithms and action go first.
    ForgetPairAlgorithms forget(dispatcher);
    world->getPairCache()->processAllOverlappingPairs(&forget, dispatcher);
  } else {
    refuseLiveRegistration(dispatcher);
  }
  system->registerWith(*dispatcher);
  Registration previous = store(dispatcher, Registration{system, world, ourPairEntry(*dispatcher)});
  if (world != nullptr && previous.world == world) world->removeAction(previous.system.get());
  if (world != nullptr) world->addAction(system.get());
  system->attachWorld(world);  // its pairs are planned and computed in parallel (sdfccd_parallel_step.cpp)
  return system;
}

}  // namespace

std::shared_ptr<SdfccdContactSystem> registerSdfccdAlgorithms(btCollisionDispatcher* dispatcher,
                                                              const SdfccdContactSettings& settings) {
  if (dispatcher == nullptr) throw Error("registerSdfccdAlgorithms: the dispatcher is null");
  return registerOwned(dispatcher, nullptr, settings);
}

std::shared_ptr<SdfccdContactSystem> registerSdfccdAlgorithms(btDiscreteDynamicsWorld* world,
                                                              const SdfccdContactSettings& settings) {
  if (world == nullptr) throw Error("registerSdfccdAlgorithms: the world is null");
  if (dynamic_cast<btDiscreteDynamicsWorldMt*>(world) != nullptr) {
    throw Error(
        "registerSdfccdAlgorithms: btDiscreteDynamicsWorldMt is not supported (the sdfccd narrowphase is "
        "single-threaded): use btDiscreteDynamicsWorld");
  }
  auto* dispatcher = dynamic_cast<btCollisionDispatcher*>(world->getDispatcher());
  if (dispatcher == nullptr)
    throw Error("registerSdfccdAlgorithms: the world's dispatcher is not a btCollisionDispatcher");
  return registerOwned(dispatcher, world, settings);
}

void releaseSdfccdAlgorithms(btDiscreteDynamicsWorld* world) {
  if (world == nullptr) return;
  auto* dispatcher = dynamic_cast<btCollisionDispatcher*>(world->getDispatcher());
  if (dispatcher == nullptr) return;
  RegistrationTable& table = registrations();
  Registration released;
  {
    const std::lock_guard<std::mutex> lock(table.mutex);
    const auto found = table.entries.find(dispatcher);
    if (found == table.entries.end()) return;
    released = std::move(found->second);
    table.entries.erase(found);
  }
  world->removeAction(released.system.get());
  released.system->attachWorld(nullptr);
  ForgetPairAlgorithms forget(dispatcher);
  world->getPairCache()->processAllOverlappingPairs(&forget, dispatcher);
  // No entry may keep pointing at the system's create functions: btEmptyAlgorithm's (one, never freed). These
  // are the entries SdfccdContactSystem::registerWith sets (every pair involving our type, both orders, both
  // query types); an entry it set beyond them would have to be reset here too.
  static btEmptyAlgorithm::CreateFunc empty;
  for (int other = 0; other < MAX_BROADPHASE_COLLISION_TYPES; ++other) {
    dispatcher->registerCollisionCreateFunc(CUSTOM_CONCAVE_SHAPE_TYPE, other, &empty);
    dispatcher->registerCollisionCreateFunc(other, CUSTOM_CONCAVE_SHAPE_TYPE, &empty);
    dispatcher->registerClosestPointsCreateFunc(CUSTOM_CONCAVE_SHAPE_TYPE, other, &empty);
    dispatcher->registerClosestPointsCreateFunc(other, CUSTOM_CONCAVE_SHAPE_TYPE, &empty);
  }
}

}  // namespace sdfccd
