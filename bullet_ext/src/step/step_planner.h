/// @file
/// @brief StepPlanner: the parallel narrowphase. The step's first pair plans the whole step: the roles of every pair
/// of ours that Bullet will process are enumerated (PairRoles) and their work queued, computed together on the
/// narrowphase pool, then taken in Bullet's pair order (see step_planner.cpp for the why).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

class btCollisionObjectWrapper;
class btCollisionWorld;
class btPersistentManifold;
struct btDispatcherInfo;

namespace sdfccd::bullet::detail {

class ContactStep;
class NarrowphasePool;
class OtherShapes;
class PairResponder;
class PairRoles;
class PenaltyResponder;
class SolverResponder;
struct PairCall;
struct RolePair;
struct SolverPair;
struct StepData;

class StepPlanner {
 public:
  /// `owner`: the step whose collision algorithms' pairs are planned.
  StepPlanner(const ContactStep* owner, StepData& data, PairRoles& roles, OtherShapes& others,
              PenaltyResponder& penalty, SolverResponder& solver);
  ~StepPlanner();
  StepPlanner(const StepPlanner&) = delete;
  StepPlanner& operator=(const StepPlanner&) = delete;

  /// The world whose overlapping pairs a step plans; null: every pair is computed when Bullet processes it.
  void attachWorld(btCollisionWorld* world) { m_world = world; }
  /// The pool is made again with the next plan when the settings' thread count changes (`threads`, resolved).
  void threadsChanged(int threads);

  /// Is the current step planned?
  bool planned() const;
  /// Plans the current step (see the file comment); once per step, at its first pair.
  void plan(const btDispatcherInfo& dispatchInfo);
  /// Did the plan compute every role of the pair of `manifold`?
  bool computed(const btPersistentManifold* manifold);
  /// Applies such a pair's results in role order through the mode's responder.
  void applyPair(const PairCall& call, PairResponder& responder);

 private:
  /// One pair of the plan: its bodies' motions, then its roles' work queued.
  void planPair(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1, double timeStep,
                btPersistentManifold* manifold, SolverPair* solverPair);
  template <class Responder>
  void queueRoles(Responder& responder, const PairCall& call, const RolePair& pair);

  const ContactStep* m_owner;
  StepData& m_data;
  PairRoles& m_roles;
  OtherShapes& m_others;
  PenaltyResponder& m_penalty;
  SolverResponder& m_solver;
  std::unique_ptr<NarrowphasePool> m_pool;
  btCollisionWorld* m_world = nullptr;
  std::vector<int> m_plannedPairs;  // the step's planned pairs (indices into the overlapping pair array)
  std::int64_t m_plannedStep = -1;  // the step counter of the last plan
};

}  // namespace sdfccd::bullet::detail
