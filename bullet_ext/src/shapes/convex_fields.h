/// @file
/// @brief The Bullet convex shapes that pair with ours (box, sphere, capsule) as analytic fields (beyond the
/// paper; see ContactSystem). Private to sdfccd::bullet.
#pragma once

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>

#include "common/bullet_conversions.h"
#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"

namespace sdfccd::bullet::detail {

/// The Bullet convex shapes our algorithm pairs with ours (each is an analytic field and a point shell).
inline bool isSupportedConvexType(int shapeType) {
  return shapeType == BOX_SHAPE_PROXYTYPE || shapeType == SPHERE_SHAPE_PROXYTYPE ||
         shapeType == CAPSULE_SHAPE_PROXYTYPE;
}
inline bool isSupportedConvex(const btCollisionShape* shape) {
  return isSupportedConvexType(shape->getShapeType());
}

/// The analytic field of a supported convex shape, centred at its body origin; calls `use(field)`. The
/// sizes include Bullet's collision margin (btBoxShape's half extents with margin are the box the user asked
/// for; a sphere's and a capsule's margin is their radius) and the local scaling.
template <class Use>
void withConvexField(const btCollisionShape* shape, Use use) {
  switch (shape->getShapeType()) {
    case BOX_SHAPE_PROXYTYPE:
      use(BoxField(toVec3(static_cast<const btBoxShape*>(shape)->getHalfExtentsWithMargin())));
      break;
    case SPHERE_SHAPE_PROXYTYPE:
      use(SphereField(Vec3::Zero(), double(static_cast<const btSphereShape*>(shape)->getRadius())));
      break;
    case CAPSULE_SHAPE_PROXYTYPE: {
      const auto* capsule = static_cast<const btCapsuleShape*>(shape);
      use(CapsuleField(double(capsule->getRadius()), double(capsule->getHalfHeight()), capsule->getUpAxis()));
      break;
    }
    default:
      throw Error("sdfccd contact: not a supported convex shape");
  }
}

}  // namespace sdfccd::bullet::detail
