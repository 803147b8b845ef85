/// @file
/// @brief PenaltyResponder: penalty mode's answer to a pair's roles (Section 4.1 and 5). Each role's work
/// (penalty_role.h) is taken from the step's plan or computed here; its result becomes manifold points, the role's
/// record, the next step's contact load and (ForceTiming::SameStep) the penalty impulses.
#pragma once

#include "step/pair_responder.h"
#include "step/step_data.h"

namespace sdfccd::bullet::detail {

struct PenaltyRoleFacts;

class PenaltyResponder final : public RoleVisitorOf<PenaltyResponder, PairResponder> {
 public:
  explicit PenaltyResponder(StepData& data) : m_data(data) {}

  void beginPair(const PairCall& call) override;
  void applyPlanned(const RoleResult& result) override { apply(result, false); }
  void endPair() override {}

  /// One role (RoleVisitor): its planned result, or its work computed now, applied.
  template <class Field>
  void visitField(const Role& role, const Field& field, double cellSize);
  /// Planning: queues the role's work in the step's batch (GridField and PlaneField).
  template <class Field>
  void queue(const Role& role, const Field& field, double cellSize);

 private:
  /// What the role's work is built from (see penalty_role.h).
  PenaltyRoleFacts facts(const Role& role, double cellSize, bool ground) const;
  /// `frame` at an address that lasts through the step: `kept` when given, a shared identity, or a copy in the
  /// batch's slots.
  const Rigid* lastingFrame(const Rigid& frame, const Rigid* kept);
  /// After a role's work (on the pool or here): statistics, manifold points, the record, the impulses (serial: it
  /// touches Bullet).
  void apply(const RoleResult& result, bool closestPointsOnly);

  StepData& m_data;
  btManifoldResult* m_resultOut = nullptr;
  double m_timeStep = 0.0;
  bool m_closestPointsOnly = false;
};

/// The record's penalty impulses, on its dynamic bodies (each its share: contact mass scaling).
void applyPenaltyImpulses(const ContactRecord& record, const BodySteps& bodies);

}  // namespace sdfccd::bullet::detail
