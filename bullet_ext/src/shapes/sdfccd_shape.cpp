/// @file
/// @brief SdfccdShape (see sdfccd_shape.h).
#include "sdfccd/bullet/sdfccd_shape.h"

#include <BulletCollision/CollisionShapes/btTriangleCallback.h>

#include <cstring>

#include "sdfccd/error.h"

namespace sdfccd::bullet {

SdfccdShape::SdfccdShape(std::shared_ptr<const BodyModel> model)
    : m_model(std::move(model)), m_queryAccel(makeQueryAccel()) {
  if (!m_model) throw Error("SdfccdShape: the body model is null");
  m_shapeType = CUSTOM_CONCAVE_SHAPE_TYPE;
  const Box3& box = m_model->boundsInBody();
  m_localAabbMin = btVector3(btScalar(box.min().x()), btScalar(box.min().y()), btScalar(box.min().z()));
  m_localAabbMax = btVector3(btScalar(box.max().x()), btScalar(box.max().y()), btScalar(box.max().z()));
}

void SdfccdShape::getAabb(const btTransform& worldFromBody, btVector3& aabbMin, btVector3& aabbMax) const {
  // The rotated local box, grown by the margin (same construction as btTransformAabb).
  const btVector3 halfExtents =
      0.5f * (m_localAabbMax - m_localAabbMin) + btVector3(getMargin(), getMargin(), getMargin());
  const btVector3 localCenter = 0.5f * (m_localAabbMax + m_localAabbMin);
  const btMatrix3x3 absBasis = worldFromBody.getBasis().absolute();
  const btVector3 center = worldFromBody(localCenter);
  const btVector3 extent(absBasis[0].dot(halfExtents), absBasis[1].dot(halfExtents), absBasis[2].dot(halfExtents));
  aabbMin = center - extent;
  aabbMax = center + extent;
}

void SdfccdShape::setLocalScaling(const btVector3& scaling) {
  if (scaling.x() != 1 || scaling.y() != 1 || scaling.z() != 1) {
    throw Error("SdfccdShape: local scaling is not supported; build the body model with a scale instead");
  }
}

void SdfccdShape::calculateLocalInertia(btScalar mass, btVector3& inertia) const {
  const Vec3 moments = m_model->principalInertia(static_cast<double>(mass));
  inertia.setValue(btScalar(moments.x()), btScalar(moments.y()), btScalar(moments.z()));
}

void SdfccdShape::processAllTriangles(btTriangleCallback* callback, const btVector3& aabbMin,
                                      const btVector3& aabbMax) const {
  if (processQuery(callback)) return;
  const TriangleMesh& mesh = m_model->meshInBody();
  btVector3 corners[3];
  for (int index = 0; index < static_cast<int>(mesh.triangles.size()); ++index) {
    const auto& tri = mesh.triangles[static_cast<std::size_t>(index)];
    btVector3 lo(BT_LARGE_FLOAT, BT_LARGE_FLOAT, BT_LARGE_FLOAT);
    btVector3 hi = -lo;
    for (int k = 0; k < 3; ++k) {
      const Vec3& v = mesh.vertices[static_cast<std::size_t>(tri[k])];
      corners[k].setValue(btScalar(v.x()), btScalar(v.y()), btScalar(v.z()));
      lo.setMin(corners[k]);
      hi.setMax(corners[k]);
    }
    if (lo.x() > aabbMax.x() || hi.x() < aabbMin.x() || lo.y() > aabbMax.y() || hi.y() < aabbMin.y() ||
        lo.z() > aabbMax.z() || hi.z() < aabbMin.z()) {
      continue;
    }
    callback->processTriangle(corners, 0, index);
  }
}

namespace {
constexpr char kShapeName[] = "SdfccdShape";
}  // namespace

const char* SdfccdShape::getName() const {
  return kShapeName;
}

bool isSdfccdShape(const btCollisionShape* shape) {
  if (shape == nullptr || shape->getShapeType() != CUSTOM_CONCAVE_SHAPE_TYPE) return false;
  // Asked for every role of every pair each step: our own name is recognised by its address, without reading it
  // (the characters are compared only for another custom concave shape, or a copy of the name from elsewhere).
  const char* name = shape->getName();
  return name == kShapeName || std::strcmp(name, kShapeName) == 0;
}

}  // namespace sdfccd::bullet
