/// @file
/// @brief OtherShapes::analyticShellTree: the surface points of a box, sphere or capsule, sampled once per shape size
/// and spacing (beyond the paper; see other_shapes.h).
#include <sstream>
#include <type_traits>

#include "roles/other_shapes.h"
#include "sdfccd/shell/analytic_shells.h"
#include "shapes/convex_fields.h"
#include "step/contact_record.h"

namespace sdfccd::bullet::detail {

const PointTree& OtherShapes::analyticShellTree(const btCollisionShape* shape, double fieldCellSize,
                                                const ContactSettings& settings) {
  // Keyed by the shape's type and sizes (not its address, which a deleted shape may hand on) and the spacing.
  std::ostringstream key;
  key.precision(17);
  double smallestExtent = 0.0;  // the shape's thinnest size (m)
  withConvexField(shape, [&](const auto& field) {
    using Field = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<Field, BoxField>) {
      key << ' ' << field.halfExtents().transpose();
      smallestExtent = 2.0 * field.halfExtents().minCoeff();
    }
    if constexpr (std::is_same_v<Field, SphereField>) {
      key << ' ' << field.radius();
      smallestExtent = 2.0 * field.radius();
    }
    if constexpr (std::is_same_v<Field, CapsuleField>) {
      key << ' ' << field.radius() << ' ' << field.halfHeight() << ' ' << field.axis();
      smallestExtent = 2.0 * field.radius();
    }
  });
  // Fine enough for the field it meets, and for the shape itself: a small sphere on a coarse field still
  // rests on a patch of points, not on one.
  const double spacing =
      std::min(settings.convexPointSpacingCells * fieldCellSize, smallestExtent / kConvexPointsAcross);
  key << ' ' << shape->getShapeType() << ' ' << spacing;
  auto found = m_analyticTrees.find(key.str());
  if (found != m_analyticTrees.end()) return *found->second;
  AnalyticShellSettings sampling;
  sampling.spacing = spacing;
  sampling.maxPoints = settings.convexMaxPoints;
  PointShell points;
  withConvexField(shape, [&](const auto& field) {
    using Field = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<Field, BoxField>) points = boxShell(field.halfExtents(), sampling);
    if constexpr (std::is_same_v<Field, SphereField>) points = sphereShell(field.radius(), sampling);
    if constexpr (std::is_same_v<Field, CapsuleField>)
      points = capsuleShell(field.radius(), field.halfHeight(), field.axis(), sampling);
  });
  auto tree = std::make_unique<PointTree>(std::move(points));
  return *m_analyticTrees.emplace(key.str(), std::move(tree)).first->second;
}

}  // namespace sdfccd::bullet::detail
