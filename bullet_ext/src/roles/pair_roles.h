/// @file
/// @brief PairRoles: the roles of one pair. Every body with a shell takes the shell role once (ours always; a
/// convex shape or a triangle mesh only against our field); each role gets the pair's material, its kept state
/// (RoleSlots) and its field, and goes to a RoleVisitor (the mode's responder, or the step planner's queue).
#pragma once

#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>

#include <cstddef>

#include "shapes/bullet_shape_fields.h"

class btPersistentManifold;

namespace sdfccd::bullet::detail {

class OtherShapes;
class RoleSlots;
class RoleVisitor;
struct StepData;

/// One pair as its roles are enumerated: the wrappers, what each shape is, the step's bodies of both.
struct RolePair {
  const btCollisionObjectWrapper* wrap0 = nullptr;
  const btCollisionObjectWrapper* wrap1 = nullptr;
  ShapeKind kind0 = ShapeKind::Unsupported;
  ShapeKind kind1 = ShapeKind::Unsupported;
  std::size_t index0 = 0;  // into the step's bodies (BodySteps)
  std::size_t index1 = 0;
  const btPersistentManifold* manifold = nullptr;
  bool closestPointsOnly = false;  // a contactTest query: no kept state

  /// The pair's wrappers and what their shapes are; the bodies' indices are set by the bodies' stage.
  RolePair(const btCollisionObjectWrapper* first, const btCollisionObjectWrapper* second,
           const btPersistentManifold* pairManifold, bool closestPoints)
      : wrap0(first),
        wrap1(second),
        kind0(shapeKind(first->getCollisionShape())),
        kind1(shapeKind(second->getCollisionShape())),
        manifold(pairManifold),
        closestPointsOnly(closestPoints) {}
};

class PairRoles {
 public:
  PairRoles(StepData& data, RoleSlots& slots, OtherShapes& others) : m_data(data), m_slots(slots), m_others(others) {}

  /// Sends each role of `pair`, in role order, with its field to `visitor`.
  void forEach(const RolePair& pair, RoleVisitor& visitor);

 private:
  StepData& m_data;
  RoleSlots& m_slots;
  OtherShapes& m_others;
};

}  // namespace sdfccd::bullet::detail
