/// @file
/// @brief PairRoles (see pair_roles.h).
#include "roles/pair_roles.h"

#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>

#include <algorithm>
#include <optional>

#include "common/bullet_conversions.h"
#include "roles/other_shapes.h"
#include "roles/role.h"
#include "roles/role_slots.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "sdfccd/response/contact_material.h"
#include "shapes/convex_fields.h"
#include "step/motion_prediction.h"
#include "step/step_data.h"

namespace sdfccd::bullet::detail {

void PairRoles::forEach(const RolePair& pair, RoleVisitor& visitor) {
  const btCollisionObjectWrapper* wrap0 = pair.wrap0;
  const btCollisionObjectWrapper* wrap1 = pair.wrap1;
  const ShapeKind kind0 = pair.kind0;
  const ShapeKind kind1 = pair.kind1;
  const bool ours0 = kind0 == ShapeKind::Ours;
  const bool ours1 = kind1 == ShapeKind::Ours;
  const ShapeKind otherKind = ours0 ? kind1 : kind0;
  const bool closestPointsOnly = pair.closestPointsOnly;
  const ContactSettings& settings = m_data.settings;

  // The pair's material, combined the Bullet way (design 2.6), unless the settings override it.
  const btCollisionObject* object0 = wrap0->getCollisionObject();
  const btCollisionObject* object1 = wrap1->getCollisionObject();
  // Per-body overrides (setBodyContact) combined; without any, the world's settings themselves (no copy per pair).
  std::optional<PenaltySettings> combined;
  if (!m_data.bodyContacts.empty()) combined = m_data.bodyContacts.combined(settings.penalty, object0, object1);
  const PenaltySettings& penalty = combined ? *combined : settings.penalty;
  const double friction =
      penalty.frictionFromBodies ? double(gCalculateCombinedFrictionCallback(object0, object1)) : penalty.friction;
  double dampingRatio = penalty.dampingRatio;
  if (penalty.dampingRatioFromRestitution) {
    const double e = double(gCalculateCombinedRestitutionCallback(object0, object1));
    dampingRatio = dampingRatioFromRestitution(std::clamp(e, 0.0, 1.0));
  }
  const bool convexOther = otherKind == ShapeKind::AnalyticConvex || otherKind == ShapeKind::Convex;
  const bool bothRoles = (ours0 && ours1) || convexOther;
  int roleIndex = 0;
  // One role: the shell of `shellWrap` (ours, or a convex's surface points) against the field of `fieldWrap`
  // (ours, or a plane's or a convex's analytic field).
  auto runRole = [&](std::size_t shell, std::size_t field, const btCollisionObjectWrapper* shellWrap,
                     const btCollisionObjectWrapper* fieldWrap, bool shellIsBody0) {
    Role role;
    role.shell = shell;
    role.field = field;
    role.shellIsBody0 = shellIsBody0;
    role.bodyFromShellChild = bodyFromChild(*shellWrap);
    role.bodyFromFieldChild = bodyFromChild(*fieldWrap);
    role.roleScale = bothRoles ? 0.5 : 1.0;
    role.friction = std::clamp(friction, 0.0, kMaxCombinedFriction);
    role.dampingRatio = dampingRatio;
    role.penalty = &penalty;
    role.manifold = pair.manifold;
    role.index = roleIndex;
    const btCollisionShape* shellShape = shellWrap->getCollisionShape();
    const btCollisionShape* fieldShape = fieldWrap->getCollisionShape();
    const bool shellOurs = (shellWrap == wrap0 ? kind0 : kind1) == ShapeKind::Ours;
    const ShapeKind fieldKind = fieldWrap == wrap0 ? kind0 : kind1;
    const bool fieldOurs = fieldKind == ShapeKind::Ours;
    const bool anchors = !closestPointsOnly && penalty.enableFriction && penalty.frictionModel == FrictionModel::Anchor;
    // The CCD history only for our shell tree against our grid field (both persistent, owned by the shapes'
    // BodyModels, and keyed by instance id) or the analytic plane and box (keyed by their values). Other shells
    // and fields are per-step objects: no history.
    const bool coherent =
        !closestPointsOnly && settings.coherentCcd && shellOurs &&
        (fieldOurs || fieldKind == ShapeKind::Plane || fieldShape->getShapeType() == BOX_SHAPE_PROXYTYPE);
    if (anchors || coherent) {  // one map lookup per role (a pile has thousands of slots)
      // The slot forgets table and history when another pair reuses the manifold.
      RoleSlot& slot = m_slots.slot(pair.manifold, roleIndex, shellWrap->getCollisionObject(),
                                    fieldWrap->getCollisionObject(), m_data.stepCounter);
      if (anchors) role.anchors = &slot.table;
      if (coherent) role.coherence = &slot.coherence;
    }
    ++roleIndex;
    // Our shell against our field or a plane may run in the step's parallel batch (deferred_queries.h).
    role.deferrable = !closestPointsOnly && shellOurs && (fieldOurs || fieldKind == ShapeKind::Plane);
    if (fieldOurs) {
      const BodyModel& fieldModel = static_cast<const SdfccdShape*>(fieldShape)->model();
      role.bodyFromField = fieldModel.bodyFromField();
      role.modelBodyFromField = &fieldModel.bodyFromField();
      if (shellOurs) {
        role.shellTree = &static_cast<const SdfccdShape*>(shellShape)->model().tree();
      } else {
        role.shellTree = (shellWrap == wrap0 ? kind0 : kind1) == ShapeKind::Mesh
                             ? m_others.meshVertexTree(role, m_data.bodies, shellShape, fieldShape)
                             : m_others.shellTree(shellShape, fieldModel.cellSize(), settings);
        if (role.shellTree == nullptr) return;
      }
      visitor.visit(role, fieldModel.field(), fieldModel.cellSize());
      return;
    }
    // An analytic field: depths are reported in cells of the shell body's own field.
    const BodyModel& shellModel = static_cast<const SdfccdShape*>(shellShape)->model();
    role.shellTree = &shellModel.tree();
    const double shellCell = shellModel.cellSize();
    if (fieldKind == ShapeKind::Plane) {
      const auto* plane = static_cast<const btStaticPlaneShape*>(fieldShape);
      const PlaneField planeField(toVec3(plane->getPlaneNormal()), double(plane->getPlaneConstant()));
      visitor.visit(role, planeField, shellCell);
    } else if (fieldKind == ShapeKind::AnalyticConvex) {
      withConvexField(fieldShape, [&](const auto& convexField) { visitor.visit(role, convexField, shellCell); });
    } else if (fieldKind == ShapeKind::Convex) {  // a cylinder's or cone's exact field, or the hull's
      if (const std::optional<RevolvedConvexField> revolved = revolvedField(fieldShape)) {
        visitor.visit(role, *revolved, shellCell);
      } else {
        visitor.visit(role, *m_others.convexField(static_cast<const btConvexShape*>(fieldShape)), shellCell);
      }
    } else {  // a triangle mesh or terrain: the triangles near the shell's motion
      // The field sits the mesh's margin off its triangles (meshTrianglesInBox): gather that much further too.
      const double reach = std::max({settings.penalty.sigma, settings.maxSpeculativeMargin, 0.0}) + shellCell +
                           double(fieldShape->getMargin());
      const std::optional<TriangleSetField> mesh =
          m_others.meshFieldNear(role, m_data.bodies, shellShape, fieldShape, reach);
      if (mesh) visitor.visit(role, *mesh, shellCell);
    }
  };
  const std::size_t index0 = pair.index0;
  const std::size_t index1 = pair.index1;
  // Every body with a shell takes the shell role once: ours always; a convex only against our field.
  if (ours0 || ours1)
    runRole(ours0 ? index0 : index1, ours0 ? index1 : index0, ours0 ? wrap0 : wrap1, ours0 ? wrap1 : wrap0, ours0);
  if (ours0 && ours1) {
    runRole(index1, index0, wrap1, wrap0, false);
  } else if (convexOther || otherKind == ShapeKind::Mesh) {  // a mesh's vertices: at full strength (roleScale)
    runRole(ours0 ? index1 : index0, ours0 ? index0 : index1, ours0 ? wrap1 : wrap0, ours0 ? wrap0 : wrap1, !ours0);
  }
}

}  // namespace sdfccd::bullet::detail
