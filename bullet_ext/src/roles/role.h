/// @file
/// @brief Role: who is the shell and who the field in one role of a pair, with the pair's material; RoleVisitor:
/// what receives each role of a pair with its field (pair_roles.h enumerates them; a responder or the step planner
/// receives them).
#pragma once

#include <cstddef>

#include "sdfccd/ccd/rigid_ccd_coherence.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/field/polytope_fields.h"
#include "sdfccd/math_types.h"
#include "sdfccd/response/friction_anchor.h"
#include "sdfccd/response/penalty_model.h"
#include "sdfccd/shell/point_tree.h"

/// Calls X(Field) for every field a role may have (the responders' explicit instantiations).
#define SDFCCD_FOR_EACH_ROLE_FIELD(X)                                                                      \
  X(GridField) X(PlaneField) X(BoxField) X(SphereField) X(CapsuleField) X(RevolvedConvexField) \
      X(ConvexPolytopeField) X(TriangleSetField)

namespace sdfccd::bullet::detail {

struct Role {
  std::size_t shell = 0;  // indices into the step's bodies (BodySteps)
  std::size_t field = 0;
  const PointTree* shellTree = nullptr;  // our model's tree, or a convex shape's surface points
  Rigid bodyFromField = Rigid::Identity();
  const Rigid* modelBodyFromField = nullptr;     // the field model's own bodyFromField (lasts), when it has one
  Rigid bodyFromShellChild = Rigid::Identity();  // the shell wrapper's frame in its body (compound child)
  Rigid bodyFromFieldChild = Rigid::Identity();  // the field wrapper's frame in its body
  bool shellIsBody0 = true;
  double roleScale = 1.0;                    // s_r: 1/2 when the pair runs both roles
  double friction = 0.0;                     // mu of the pair (combined, or the settings' override)
  double dampingRatio = -1.0;                // zeta of the pair (from its restitution, or the settings')
  const PenaltySettings* penalty = nullptr;  // the pair's penalty parameters (per-body overrides combined)
  FrictionAnchorTable* anchors = nullptr;    // this pair and role's anchors, kept across steps
  RigidCcdCoherence* coherence = nullptr;    // this pair and role's CCD front, kept across steps
  const void* manifold = nullptr;            // with `index`: the key of a planned query (deferred_queries.h)
  int index = 0;                             // the role's index in its pair
  bool deferrable = false;                   // our shell against our field or a plane: may run in the batch
};

/// Receives one role with its field, for every kind of field a role may have. `cellSize`: the cell the role's
/// depths are measured in (the field's own, or the shell body's for an analytic field).
class RoleVisitor {
 public:
  virtual void visit(const Role& role, const GridField& field, double cellSize) = 0;
  virtual void visit(const Role& role, const PlaneField& field, double cellSize) = 0;
  virtual void visit(const Role& role, const BoxField& field, double cellSize) = 0;
  virtual void visit(const Role& role, const SphereField& field, double cellSize) = 0;
  virtual void visit(const Role& role, const CapsuleField& field, double cellSize) = 0;
  virtual void visit(const Role& role, const RevolvedConvexField& field, double cellSize) = 0;
  virtual void visit(const Role& role, const ConvexPolytopeField& field, double cellSize) = 0;
  virtual void visit(const Role& role, const TriangleSetField& field, double cellSize) = 0;

 protected:
  ~RoleVisitor() = default;
};

/// A RoleVisitor whose every visit calls Derived::visitField<Field>(role, field, cellSize).
template <class Derived, class Base = RoleVisitor>
class RoleVisitorOf : public Base {
 public:
  void visit(const Role& r, const GridField& f, double c) final { self().visitField(r, f, c); }
  void visit(const Role& r, const PlaneField& f, double c) final { self().visitField(r, f, c); }
  void visit(const Role& r, const BoxField& f, double c) final { self().visitField(r, f, c); }
  void visit(const Role& r, const SphereField& f, double c) final { self().visitField(r, f, c); }
  void visit(const Role& r, const CapsuleField& f, double c) final { self().visitField(r, f, c); }
  void visit(const Role& r, const RevolvedConvexField& f, double c) final { self().visitField(r, f, c); }
  void visit(const Role& r, const ConvexPolytopeField& f, double c) final { self().visitField(r, f, c); }
  void visit(const Role& r, const TriangleSetField& f, double c) final { self().visitField(r, f, c); }

 protected:
  ~RoleVisitorOf() = default;

 private:
  Derived& self() { return static_cast<Derived&>(*this); }
};

}  // namespace sdfccd::bullet::detail
