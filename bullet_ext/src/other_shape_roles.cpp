/// @file
/// @brief SdfccdContactSystem's roles with Bullet shapes that are not ours (beyond the paper; see
/// bullet_shape_fields.h): a convex shape's shell, a triangle mesh's triangles near our body, and the
/// announcement of a pair we cannot handle.
#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <BulletCollision/CollisionShapes/btConvexShape.h>

#include <algorithm>
#include <iostream>

#include "bullet_conversions.h"
#include "bullet_shape_fields.h"
#include "contact_step.h"
#include "sdfccd/bullet/sdfccd_contact_system.h"

namespace sdfccd {

const PointTree* SdfccdContactSystem::otherShellTree(const btCollisionShape* shape, double fieldCellSize) {
  if (detail::shapeKind(shape) == detail::ShapeKind::AnalyticConvex) return &convexShellTree(shape, fieldCellSize);
  const auto* convex = static_cast<const btConvexShape*>(shape);
  // As for the analytic shapes: fine enough for the field it meets and for the shape itself.
  const double spacing = std::min(m_settings.convexPointSpacingCells * fieldCellSize,
                                  m_convexShapes->thinnestExtent(convex) / detail::kConvexPointsAcross);
  if (!(spacing > 0.0)) return nullptr;
  return m_convexShapes->shell(convex, spacing, m_settings.convexMaxPoints);
}

void SdfccdContactSystem::reportUnsupported(const btCollisionShape* shape0, const btCollisionShape* shape1) {
  ++m_stats.unsupportedPairs;
  const int type0 = shape0->getShapeType();
  const int type1 = shape1->getShapeType();
  if (!m_announcedPairs.insert({std::min(type0, type1), std::max(type0, type1)}).second) return;
  const std::string line = std::string("sdfccd contact: no contact between a ") + shape0->getName() + " (type " +
                           std::to_string(type0) + ") and a " + shape1->getName() + " (type " + std::to_string(type1) +
                           "): this pair of shape types is not supported (counted in " +
                           "SdfccdContactStatistics::unsupportedPairs; announced once)";
  if (m_log) m_log(line);
}

std::optional<TriangleSetField> SdfccdContactSystem::meshFieldNear(const Role& role, const btCollisionShape* shellShape,
                                                                   const btCollisionShape* meshShape,
                                                                   double pad) const {
  // Every segment the rigid CCD walks runs, in the mesh's frame, from a shell point's start to its end: inside
  // the box of the shell's box at the start and at the end, both seen from the mesh at that time.
  btVector3 low, high;
  shellShape->getAabb(btTransform::getIdentity(), low, high);
  const Box3 shellBox(detail::toVec3(low), detail::toVec3(high));
  const BodyStep& shell = m_bodies[role.shell];
  const BodyStep& mesh = m_bodies[role.field];
  const Rigid meshFromShellStart = (mesh.worldFromBodyStart * role.bodyFromFieldChild).inverse() *
                                   shell.worldFromBodyStart * role.bodyFromShellChild;
  const Rigid meshFromShellEnd =
      (mesh.worldFromBodyEnd * role.bodyFromFieldChild).inverse() * shell.worldFromBodyEnd * role.bodyFromShellChild;
  Box3 box;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p = shellBox.corner(static_cast<Box3::CornerType>(corner));
    box.extend(meshFromShellStart * p);
    box.extend(meshFromShellEnd * p);
  }
  box.min().array() -= pad;
  box.max().array() += pad;
  // One-sided towards the shell's centre, as deep as half its thinnest size: a point deeper than that could be
  // past the mesh with its body (a thin wall's other side), not sinking into it.
  return detail::meshTrianglesInBox(meshShape, box, 0.5 * shellBox.sizes().minCoeff(),
                                    meshFromShellStart * shellBox.center());
}

}  // namespace sdfccd
