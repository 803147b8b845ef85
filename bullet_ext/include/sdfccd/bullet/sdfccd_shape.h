/// @file
/// @brief SdfccdShape: the Bullet collision shape of a body that carries a point shell and a distance field
/// (paper Section 5: "each bunny carries a pointshell and a signed distance field").
///
/// @details The shape holds a shared, immutable BodyModel; any number of shapes and bodies may share
/// one model. Contacts come from the collision algorithm a ContactSystem (contact_system.h) installs.
///
/// Shape type, chosen knowingly: CUSTOM_CONCAVE_SHAPE_TYPE (29), with btConcaveShape as the base class.
/// - Bullet casts a concave-range shape to btConcaveShape in rayTest, convexSweepTest and debug drawing and
///   calls processAllTriangles(): this shape serves its mesh's triangles there, so ray casts, sweeps and
///   debug drawing work on the true (concave) surface. A convex-range id would make Bullet treat the shape as
///   a convex support mapping, which a bowl or a bunny is not.
/// - 29 is also SDF_SHAPE_PROXYTYPE: Bullet's default convex-vs-concave algorithm would cast this shape to
///   btSdfCollisionShape. A ContactSystem therefore overwrites *every* dispatcher entry that
///   involves type 29, both orders, for contacts and closest points: (ours, ours), (ours, static plane) and
///   (ours, box | sphere | capsule) get our algorithm; every other pair gets btEmptyAlgorithm (no contact;
///   counted in the contact system's statistics). Consequence: btSdfCollisionShape cannot be used in the same world.
/// - Bullet's own swept-sphere CCD runs only for convex shapes, so it never interferes with ours.
///
/// Scaling: uniform scale is baked into the model when it is built (BodyModelSettings::scale);
/// setLocalScaling() accepts only (1, 1, 1) and throws sdfccd::Error otherwise.
///
/// Queries (btCollisionWorld::rayTest, convexSweepTest): Bullet hands a concave shape only
/// processAllTriangles(callback, box). The shape recognises Bullet's ray and convex-cast callbacks
/// (btTriangleRaycastCallback, btTriangleConvexcastCallback) and runs the field's exact segment query to find
/// where along the ray (or the swept shape's path) the surface can be; only the mesh triangles there go to
/// Bullet's own per-triangle test (sdfccd_shape_queries.cpp). The hits are the triangle mesh's: same hit
/// fraction, the triangle's normal (flipped towards the ray's start as Bullet does), the triangle's index in
/// LocalShapeInfo::m_triangleIndex (part 0), Bullet's flags honoured. A ray starting inside reports where it
/// leaves the surface, as for a btBvhTriangleMeshShape; an all-hits ray callback sees every crossing once. Sweeps
/// report the closest hit (Bullet's convex-cast callback never lowers its m_hitFraction, so the shape runs
/// Bullet's per-triangle cast itself to stop there; farther hits are not reported). Cost: at most that of a
/// btBvhTriangleMeshShape of the same mesh (`sdfccd bench queries`). Any other triangle callback gets every
/// triangle overlapping its box.
///
/// Ownership: the shape shares the model (std::shared_ptr); the user owns the shape and must keep it alive as
/// long as a btCollisionObject uses it (Bullet's rule for every shape). The query tables are built on the first
/// ray or sweep (thread safe) and owned by the shape.
#pragma once

#include <BulletCollision/CollisionShapes/btConcaveShape.h>

#include <memory>

#include "sdfccd/model/body_model.h"

namespace sdfccd::bullet {

ATTRIBUTE_ALIGNED16(class) SdfccdShape : public btConcaveShape {
 public:
  BT_DECLARE_ALIGNED_ALLOCATOR();

  /// Throws sdfccd::Error if `model` is null.
  explicit SdfccdShape(std::shared_ptr<const BodyModel> model);

  const BodyModel& model() const {
    return *m_model;
  }
  const std::shared_ptr<const BodyModel>& modelPtr() const {
    return m_model;
  }
  /// The mesh's box in the body frame, without the margin (as btBvhTriangleMeshShape::getLocalAabbMin/Max).
  const btVector3& getLocalAabbMin() const {
    return m_localAabbMin;
  }
  const btVector3& getLocalAabbMax() const {
    return m_localAabbMax;
  }

  void getAabb(const btTransform& worldFromBody, btVector3& aabbMin, btVector3& aabbMax) const override;
  /// Throws sdfccd::Error unless `scaling` is (1, 1, 1): scale the model instead.
  void setLocalScaling(const btVector3& scaling) override;
  const btVector3& getLocalScaling() const override {
    return m_localScaling;
  }
  /// The principal moments of the mesh's solid for `mass` (the body frame is the principal frame).
  void calculateLocalInertia(btScalar mass, btVector3 & inertia) const override;
  /// "SdfccdShape", always the same pointer (isSdfccdShape compares it before the characters).
  const char* getName() const override;
  /// Ray tests and convex sweeps: the triangles near the surface crossings the field finds (see "Queries"
  /// above); any other callback (debug draw, ...): the mesh triangles whose box overlaps [aabbMin, aabbMax]
  /// (body frame).
  void processAllTriangles(btTriangleCallback * callback, const btVector3& aabbMin, const btVector3& aabbMax)
      const override;

 private:
  struct QueryAccel;
  static std::shared_ptr<QueryAccel> makeQueryAccel();
  const QueryAccel& queryAccel() const;
  /// Ray or sweep callbacks: true when `callback` was one and has been served.
  bool processQuery(btTriangleCallback * callback) const;
  /// Hands `callback` the triangles within `radius` (plus the field's band) of the path from -> to (body frame)
  /// wherever the field allows a crossing, up to the callback's current `hitFraction`.
  void feedTrianglesNear(btTriangleCallback * callback, const btScalar& hitFraction, const Vec3& from, const Vec3& to,
                         double radius) const;

  std::shared_ptr<const BodyModel> m_model;
  std::shared_ptr<QueryAccel> m_queryAccel;
  btVector3 m_localScaling{1, 1, 1};
  btVector3 m_localAabbMin;
  btVector3 m_localAabbMax;
};

/// True when `shape` is an SdfccdShape (type 29 and our name: btSdfCollisionShape shares the type id).
bool isSdfccdShape(const btCollisionShape* shape);

}  // namespace sdfccd::bullet
