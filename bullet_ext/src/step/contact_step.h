/// @file
/// @brief ContactStep: the contact inside Bullet's step (the state behind ContactSystem). Bullet calls processPair
/// for each of our pairs in the narrowphase (through CollisionAlgorithm) and updateAction after integrateTransforms
/// (this is the world's action). processPair reads as the list of a pair's stages (contact_step.cpp).
#pragma once

#include <BulletDynamics/Dynamics/btActionInterface.h>

#include <memory>
#include <vector>

#include "penalty/penalty_responder.h"
#include "roles/other_shapes.h"
#include "roles/pair_roles.h"
#include "roles/role_slots.h"
#include "sdfccd/bullet/contact_system.h"
#include "solver/solver_responder.h"
#include "step/step_data.h"
#include "step/step_planner.h"

class btCollisionAlgorithmCreateFunc;
class btCollisionDispatcher;
class btCollisionObjectWrapper;
class btManifoldResult;
class btPersistentManifold;
struct btDispatcherInfo;

namespace sdfccd::bullet::detail {

class ContactStep : public btActionInterface {
 public:
  explicit ContactStep(const ContactSettings& settings);
  ~ContactStep() override;
  ContactStep(const ContactStep&) = delete;
  ContactStep& operator=(const ContactStep&) = delete;

  const ContactSettings& settings() const { return m_data.settings; }
  /// Throws sdfccd::Error on bad values (validateContactSettings).
  void setSettings(const ContactSettings& settings);
  StepData& data() { return m_data; }
  const StepData& data() const { return m_data; }
  void setLogCallback(LogCallback callback) { m_log = std::move(callback); }

  /// The create functions of our algorithm, owned here, in every dispatcher entry involving our shape type.
  void registerWith(btCollisionDispatcher& dispatcher);
  /// The world whose pairs each step plans (StepPlanner); null detaches.
  void attachWorld(btCollisionWorld* world) { m_planner.attachWorld(world); }

  /// One pair of ours, as Bullet dispatches it (CollisionAlgorithm). `closestPointsOnly`: a contactTest query,
  /// which reports the points inside at the current poses and changes nothing. `solverPair`: the algorithm's
  /// solver-mode state; null in penalty mode.
  void processPair(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                   const btDispatcherInfo& dispatchInfo, btManifoldResult* resultOut, btPersistentManifold* manifold,
                   SolverPair* solverPair, bool closestPointsOnly);

  /// btActionInterface: after integrateTransforms, the step's response and report (step_response.cpp).
  void updateAction(btCollisionWorld* world, btScalar timeStep) override;
  void debugDraw(btIDebugDraw*) override {}

  const std::vector<PairContact>& lastContacts() const { return m_lastContacts; }
  int lastContactCount() const { return m_lastContactCount; }
  double lastMaxPenetrationCells() const { return m_lastMaxPenetrationCells; }
  int lastClamps() const { return m_lastClamps; }

 private:
  /// The clamps, the impacts and the kinematic pushes of the step's records (step_response.cpp).
  void clampAndImpact();
  /// The NextStep penalty impulses and the step's contact report (step_response.cpp).
  void applyAndReport();

  StepData m_data;
  RoleSlots m_slots;
  OtherShapes m_others;
  PairRoles m_roles{m_data, m_slots, m_others};
  PenaltyResponder m_penalty{m_data};
  SolverResponder m_solver{m_data};
  StepPlanner m_planner{this, m_data, m_roles, m_others, m_penalty, m_solver};
  LogCallback m_log;  // announcements (stderr unless set)
  std::vector<std::unique_ptr<btCollisionAlgorithmCreateFunc>> m_createFuncs;
  std::vector<PairContact> m_lastContacts;
  int m_lastContactCount = 0;
  double m_lastMaxPenetrationCells = 0.0;
  int m_lastClamps = 0;
};

/// Throws sdfccd::Error on bad settings (contact_settings.cpp).
void validateContactSettings(const ContactSettings& settings);

/// The library's own way into a ContactSystem's step (the benchmarks' hooks: internal.h).
struct ContactSystemAccess {
  static ContactStep& step(ContactSystem& system) { return *system.m_step; }
};

}  // namespace sdfccd::bullet::detail
