/// @file
/// @brief The CSG static objects of haptic scenes (haptic_scene.h): exact signed distances of the primitives
/// (boxes, cylinders about any axis, capsules), their union minus the holes, and sampling on a grid.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "sdfccd/error.h"
#include "sdfccd/haptics/haptic_scene.h"

namespace sdfccd::haptics {

double CsgPrimitive::signedDistance(const Vec3& p) const {
  switch (kind) {
    case Kind::Box: {
      const Vec3 q = (p - center).cwiseAbs() - halfExtents;
      return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
    }
    case Kind::Cylinder: {
      const Vec3 d3 = p - center;
      const double along = d3.dot(axis);
      const double radial = (d3 - along * axis).norm() - radius;
      const double axial = std::abs(along) - halfHeight;
      return std::min(std::max(radial, axial), 0.0) + std::hypot(std::max(radial, 0.0), std::max(axial, 0.0));
    }
    case Kind::Capsule: {
      const Vec3 segment = end - center;
      const double lengthSquared = segment.squaredNorm();
      const double u = lengthSquared > 0.0 ? std::clamp((p - center).dot(segment) / lengthSquared, 0.0, 1.0) : 0.0;
      return (p - (center + u * segment)).norm() - radius;
    }
  }
  return 0.0;
}

Box3 CsgPrimitive::bounds() const {
  const auto bad = [] { throw Error("obstacle: a solid has a non-positive or non-finite size"); };
  Box3 box;
  switch (kind) {
    case Kind::Box:
      if (!center.allFinite() || !halfExtents.allFinite() || !(halfExtents.minCoeff() > 0.0)) bad();
      box.extend(center - halfExtents);
      box.extend(center + halfExtents);
      break;
    case Kind::Cylinder: {
      if (!center.allFinite() || !std::isfinite(radius) || !std::isfinite(halfHeight) || !(radius > 0.0) ||
          !(halfHeight > 0.0) || !(std::abs(axis.norm() - 1.0) < 1e-9))
        bad();
      // Per world axis i: the end discs reach halfHeight |a_i| + radius sqrt(1 - a_i^2) from the centre.
      Vec3 half;
      for (int i = 0; i < 3; ++i)
        half[i] = halfHeight * std::abs(axis[i]) + radius * std::sqrt(std::max(0.0, 1.0 - axis[i] * axis[i]));
      box.extend(center - half);
      box.extend(center + half);
      break;
    }
    case Kind::Capsule:
      if (!center.allFinite() || !end.allFinite() || !std::isfinite(radius) || !(radius > 0.0)) bad();
      box.extend(center.cwiseMin(end) - Vec3::Constant(radius));
      box.extend(center.cwiseMax(end) + Vec3::Constant(radius));
      break;
  }
  return box;
}

double CsgObstacle::signedDistance(const Vec3& p) const {
  double solid = 1e300;
  for (const CsgPrimitive& s : solids) solid = std::min(solid, s.signedDistance(p));
  double hole = 1e300;
  for (const CsgPrimitive& h : holes) hole = std::min(hole, h.signedDistance(p));
  return holes.empty() ? solid : std::max(solid, -hole);
}

std::shared_ptr<const SdfGrid> sampleCsgObstacle(const CsgObstacle& obstacle) {
  if (obstacle.solids.empty()) throw Error("obstacle: no solids");
  if (!(obstacle.spacing > 0.0) || !std::isfinite(obstacle.spacing)) throw Error("obstacle: spacing must be > 0");
  if (obstacle.paddingCells < 0 || obstacle.paddingCells > 1000) throw Error("obstacle: paddingCells out of range");
  if (!std::isfinite(obstacle.offsetCells)) throw Error("obstacle: offsetCells is not finite");
  Box3 box;
  for (const CsgPrimitive& s : obstacle.solids) box.extend(s.bounds());
  for (const CsgPrimitive& s : obstacle.holes) (void)s.bounds();  // checks the holes' sizes too
  const double h = obstacle.spacing;
  const Vec3 origin = box.min() - Vec3::Constant(obstacle.paddingCells * h);
  const Vec3 size = box.sizes() + Vec3::Constant(2.0 * obstacle.paddingCells * h);
  Vec3i nodes;
  double total = 1.0;
  double perAxis[3];
  for (int a = 0; a < 3; ++a) {
    perAxis[a] = std::ceil(size[a] / h - 1e-9) + 1.0;  // a double: checked before any cast to int
    total *= perAxis[a];
  }
  if (!(total <= 64.0 * 1024 * 1024)) throw Error("obstacle: grid too large (over 64 M nodes); raise the spacing");
  for (int a = 0; a < 3; ++a) nodes[a] = static_cast<int>(perAxis[a]);
  std::vector<float> values(static_cast<std::size_t>(total));
  const double offset = obstacle.offsetCells * h;
  std::size_t n = 0;
  for (int k = 0; k < nodes.z(); ++k)
    for (int j = 0; j < nodes.y(); ++j)
      for (int i = 0; i < nodes.x(); ++i)
        values[n++] = static_cast<float>(obstacle.signedDistance(origin + h * Vec3(i, j, k)) - offset);
  return std::make_shared<const SdfGrid>(nodes, origin, h, std::move(values));
}

}  // namespace sdfccd::haptics
