/// @file
/// @brief OtherShapes (see other_shapes.h): shells of convex shapes, triangle meshes' roles, unsupported pairs.
#include "roles/other_shapes.h"

#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <BulletCollision/CollisionShapes/btConvexShape.h>

#include <algorithm>
#include <array>
#include <map>

#include "common/bullet_conversions.h"
#include "roles/role.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "step/body_steps.h"
#include "step/contact_record.h"

namespace sdfccd::bullet::detail {

OtherShapes::OtherShapes() = default;
OtherShapes::~OtherShapes() = default;

const PointTree* OtherShapes::shellTree(const btCollisionShape* shape, double fieldCellSize,
                                        const ContactSettings& settings) {
  if (shapeKind(shape) == ShapeKind::AnalyticConvex) return &analyticShellTree(shape, fieldCellSize, settings);
  const auto* convex = static_cast<const btConvexShape*>(shape);
  // As for the analytic shapes: fine enough for the field it meets and for the shape itself.
  const double spacing = std::min(settings.convexPointSpacingCells * fieldCellSize,
                                  m_convexShapes.thinnestExtent(convex) / kConvexPointsAcross);
  if (!(spacing > 0.0)) return nullptr;
  return m_convexShapes.shell(convex, spacing, settings.convexMaxPoints);
}

void OtherShapes::reportUnsupported(const btCollisionShape* shape0, const btCollisionShape* shape1,
                                    ContactStatistics& stats, const LogCallback& log) {
  ++stats.unsupportedPairs;
  const int type0 = shape0->getShapeType();
  const int type1 = shape1->getShapeType();
  if (!m_announcedPairs.insert({std::min(type0, type1), std::max(type0, type1)}).second) return;
  const std::string line = std::string("sdfccd contact: no contact between a ") + shape0->getName() + " (type " +
                           std::to_string(type0) + ") and a " + shape1->getName() + " (type " + std::to_string(type1) +
                           "): this pair of shape types is not supported (counted in " +
                           "ContactStatistics::unsupportedPairs; announced once)";
  if (log) log(line);
}

namespace {

/// The box, in B's frame, of shape A's box (in its own frame) at the step's start and at its end: every segment
/// the rigid CCD walks between A's points and B lies in it. `outShapeBox`: A's box in its frame.
Box3 sweptBoxIn(const btCollisionShape* shapeA, const Rigid& worldFromAStart, const Rigid& worldFromAEnd,
                const Rigid& worldFromBStart, const Rigid& worldFromBEnd, Box3& outShapeBox) {
  btVector3 low, high;
  shapeA->getAabb(btTransform::getIdentity(), low, high);
  outShapeBox = Box3(toVec3(low), toVec3(high));
  const Rigid bFromAStart = worldFromBStart.inverse() * worldFromAStart;
  const Rigid bFromAEnd = worldFromBEnd.inverse() * worldFromAEnd;
  Box3 box;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p = outShapeBox.corner(static_cast<Box3::CornerType>(corner));
    box.extend(bFromAStart * p);
    box.extend(bFromAEnd * p);
  }
  return box;
}

}  // namespace

std::optional<TriangleSetField> OtherShapes::meshFieldNear(const Role& role, const BodySteps& bodies,
                                                          const btCollisionShape* shellShape,
                                                          const btCollisionShape* meshShape, double pad) const {
  const BodyStep& shell = bodies[role.shell];
  const BodyStep& mesh = bodies[role.field];
  const Rigid worldFromMeshStart = mesh.worldFromBodyStart * role.bodyFromFieldChild;
  const Rigid worldFromShellStart = shell.worldFromBodyStart * role.bodyFromShellChild;
  Box3 shellBox;
  Box3 box = sweptBoxIn(shellShape, worldFromShellStart, shell.worldFromBodyEnd * role.bodyFromShellChild,
                        worldFromMeshStart, mesh.worldFromBodyEnd * role.bodyFromFieldChild, shellBox);
  box.min().array() -= pad;
  box.max().array() += pad;
  // One-sided towards the shell's centre, as deep as half its thinnest size: a point deeper than that could be
  // past the mesh with its body (a thin wall's other side), not sinking into it.
  return meshTrianglesInBox(meshShape, box, 0.5 * shellBox.sizes().minCoeff(),
                                    worldFromMeshStart.inverse() * worldFromShellStart * shellBox.center());
}

const PointTree* OtherShapes::meshVertexTree(const Role& role, const BodySteps& bodies,
                                             const btCollisionShape* meshShape, const btCollisionShape* ourShape) {
  const BodyStep& mesh = bodies[role.shell];
  const BodyStep& ours = bodies[role.field];
  const Rigid worldFromMeshStart = mesh.worldFromBodyStart * role.bodyFromShellChild;
  const Rigid worldFromOursStart = ours.worldFromBodyStart * role.bodyFromFieldChild;
  Box3 ourBox;
  const Box3 box = sweptBoxIn(ourShape, worldFromOursStart, ours.worldFromBodyEnd * role.bodyFromFieldChild,
                              worldFromMeshStart, mesh.worldFromBodyEnd * role.bodyFromShellChild, ourBox);
  std::vector<Vec3> corners;
  std::vector<TriangleIndices> triangles;
  meshTriangles(meshShape, box, corners, triangles);
  // Each vertex inside the box once, its normal the sum of its triangles' normals turned towards our body.
  const Vec3 ourCentre = worldFromMeshStart.inverse() * worldFromOursStart * ourBox.center();
  std::map<std::array<double, 3>, std::size_t> seen;
  PointShell points;
  for (const TriangleIndices& t : triangles) {
    const Vec3& a = corners[static_cast<std::size_t>(t[0])];
    Vec3 n = (corners[static_cast<std::size_t>(t[1])] - a).cross(corners[static_cast<std::size_t>(t[2])] - a);
    if (!(n.norm() > 0.0)) continue;
    n.normalize();
    if (n.dot(ourCentre - a) < 0.0) n = -n;
    for (int i : t) {
      const Vec3& v = corners[static_cast<std::size_t>(i)];
      if (!box.contains(v)) continue;
      const auto found = seen.emplace(std::array<double, 3>{v.x(), v.y(), v.z()}, points.positions.size());
      if (found.second) {
        points.positions.push_back(v);
        points.normals.push_back(n);
      } else {
        points.normals[found.first->second] += n;
      }
    }
  }
  if (points.empty()) return nullptr;
  for (Vec3& n : points.normals) n.normalize();
  // Each vertex stands for one of our shell's points (the per-area penalty law).
  const PointShell& ourShell = static_cast<const SdfccdShape*>(ourShape)->model().shell();
  assignUniformAreas(points, ourShell.totalArea() / double(ourShell.size()) * double(points.size()));
  m_meshVertices = std::make_unique<PointTree>(std::move(points));
  return m_meshVertices.get();
}

}  // namespace sdfccd::bullet::detail
