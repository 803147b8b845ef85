/// @file
/// @brief OtherShapes: the roles of Bullet shapes that are not ours (beyond the paper; see shapes/bullet_shape_fields.h):
/// a convex shape's shell and field (cached), a triangle mesh's triangles near our body and its vertices there, and
/// the announcement of a pair we cannot handle. Stepping thread only (their roles never run in the parallel batch).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>

#include "sdfccd/bullet/contact_settings.h"
#include "sdfccd/field/polytope_fields.h"
#include "sdfccd/shell/point_tree.h"
#include "shapes/bullet_shape_fields.h"

class btCollisionShape;
class btConvexShape;

namespace sdfccd::bullet::detail {

class BodySteps;
struct Role;

class OtherShapes {
 public:
  OtherShapes();
  ~OtherShapes();
  OtherShapes(const OtherShapes&) = delete;
  OtherShapes& operator=(const OtherShapes&) = delete;

  /// The field of a Convex shape (ConvexShapeCache::field): null for a degenerate one.
  const ConvexPolytopeField* convexField(const btConvexShape* shape) { return m_convexShapes.field(shape); }
  /// The shell of a shape that is not ours (box, sphere, capsule or any other convex shape; cached), spaced for
  /// a field of `fieldCellSize`; null for a degenerate convex shape.
  const PointTree* shellTree(const btCollisionShape* shape, double fieldCellSize, const ContactSettings& settings);
  /// A triangle mesh's role as field: its triangles within `pad` of the box the shell sweeps over the step
  /// (relative to the mesh), in the mesh's frame; nothing when there are none.
  std::optional<TriangleSetField> meshFieldNear(const Role& role, const BodySteps& bodies,
                                                const btCollisionShape* shellShape, const btCollisionShape* meshShape,
                                                double pad) const;
  /// A triangle mesh's role as shell: its vertices in the box our body (the role's field) sweeps, each with the
  /// normal of its triangles turned towards our body; null when there are none. Valid until the next call.
  const PointTree* meshVertexTree(const Role& role, const BodySteps& bodies, const btCollisionShape* meshShape,
                                  const btCollisionShape* ourShape);
  /// Counts an unsupported pair and announces its shape types once (through `log`).
  void reportUnsupported(const btCollisionShape* shape0, const btCollisionShape* shape1, ContactStatistics& stats,
                         const LogCallback& log);
  /// Once per step: cached convex shapes unused for `idleSteps` steps go.
  void evictIdle(std::int64_t now, std::int64_t idleSteps) { m_convexShapes.evictIdle(now, idleSteps); }

 private:
  /// The surface points of a supported analytic convex shape at the spacing for a field of `fieldCellSize`
  /// (cached; convex_shells.cpp).
  const PointTree& analyticShellTree(const btCollisionShape* shape, double fieldCellSize,
                                     const ContactSettings& settings);

  std::unordered_map<std::string, std::unique_ptr<PointTree>> m_analyticTrees;  // by shape type, sizes, spacing
  ConvexShapeCache m_convexShapes;            // other convex shapes' fields and shells
  std::unique_ptr<PointTree> m_meshVertices;  // the current mesh role's vertices (one role at a time)
  std::set<std::pair<int, int>> m_announcedPairs;  // shape type pairs announced unsupported
};

}  // namespace sdfccd::bullet::detail
