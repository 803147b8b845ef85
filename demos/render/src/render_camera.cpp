/// @file
/// @brief RenderCamera: look-at and perspective matrices, projection to pixels, automatic framing.
#include "sdfccd/render/render_camera.h"

#include <algorithm>
#include <cmath>

#include "sdfccd/error.h"

namespace sdfccd::render {

namespace {

double degreesToRadians(double degrees) {
  return degrees * kPi / 180.0;
}

bool isFinite(const Vec3& v) {
  return v.allFinite();
}

}  // namespace

void RenderCamera::validate() const {
  if (!isFinite(eye) || !isFinite(target) || !isFinite(up)) throw Error("camera: eye, target and up must be finite");
  if (!(fovDegrees > 0.0 && fovDegrees < 179.0)) {
    throw Error("camera: fov must be in (0, 179) degrees, got " + std::to_string(fovDegrees));
  }
  const Vec3 forward = target - eye;
  if (forward.norm() <= 1e-12) throw Error("camera: eye and target are the same point");
  if (up.norm() <= 1e-12 || forward.normalized().cross(up.normalized()).norm() < 1e-6) {
    throw Error("camera: the up direction is zero or along the view direction");
  }
}

Rigid RenderCamera::viewFromWorld() const {
  validate();
  const Vec3 back = (eye - target).normalized();   // camera +z (it looks down -z)
  const Vec3 right = up.cross(back).normalized();  // camera +x
  const Vec3 cameraUp = back.cross(right);         // camera +y
  Mat3 worldFromViewRotation;
  worldFromViewRotation.col(0) = right;
  worldFromViewRotation.col(1) = cameraUp;
  worldFromViewRotation.col(2) = back;
  Rigid worldFromView = Rigid::Identity();
  worldFromView.linear() = worldFromViewRotation;
  worldFromView.translation() = eye;
  return worldFromView.inverse(Eigen::Isometry);
}

Eigen::Matrix4d RenderCamera::projection(double aspect, double nearDistance, double farDistance) const {
  // The glFrustum/gluPerspective matrix, written out so the tests can use exactly what GL gets.
  const double f = 1.0 / std::tan(0.5 * degreesToRadians(fovDegrees));
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (farDistance + nearDistance) / (nearDistance - farDistance);
  m(2, 3) = 2.0 * farDistance * nearDistance / (nearDistance - farDistance);
  m(3, 2) = -1.0;
  return m;
}

PixelProjection projectToPixel(const RenderCamera& camera, const Vec3& pointInWorld, int width, int height) {
  PixelProjection result;
  const Vec3 pointInView = camera.viewFromWorld() * pointInWorld;
  result.depth = -pointInView.z();
  result.inFront = result.depth > 0.0;
  if (!result.inFront) return result;
  const double f = 1.0 / std::tan(0.5 * degreesToRadians(camera.fovDegrees));
  const double aspect = static_cast<double>(width) / height;
  const double ndcX = f / aspect * pointInView.x() / result.depth;
  const double ndcY = f * pointInView.y() / result.depth;
  // Viewport transform; image rows run downwards while GL window rows run upwards.
  result.pixel = Eigen::Vector2d(0.5 * (ndcX + 1.0) * width, 0.5 * (1.0 - ndcY) * height);
  result.inImage =
      result.pixel.x() >= 0.0 && result.pixel.x() < width && result.pixel.y() >= 0.0 && result.pixel.y() < height;
  return result;
}

RenderCamera framePoints(const std::vector<Vec3>& pointsInWorld, double aspect, const CameraFramingSettings& settings) {
  if (!(aspect > 0.0) || !std::isfinite(aspect)) throw Error("camera framing: bad image aspect ratio");
  if (!settings.viewDirection.allFinite() || settings.viewDirection.norm() <= 1e-12) {
    throw Error("camera framing: the view direction must be finite and non-zero");
  }
  if (!(settings.margin >= 1.0) || !std::isfinite(settings.margin)) throw Error("camera framing: margin must be >= 1");
  if (!(settings.fovDegrees > 0.0 && settings.fovDegrees < 179.0)) throw Error("camera framing: bad field of view");
  Box3 box;
  for (const Vec3& p : pointsInWorld) {
    if (!p.allFinite()) throw Error("camera framing: the scene bounds are not finite");
    box.extend(p);
  }
  std::vector<Vec3> points = pointsInWorld;
  if (!(settings.minimumSize > 0.0) || !std::isfinite(settings.minimumSize)) {
    throw Error("camera framing: the minimum size must be > 0");
  }
  if (box.isEmpty() || (box.sizes().array() < settings.minimumSize).all()) {
    // Nothing (or almost nothing) to frame: a box of the minimum size around it.
    const Vec3 centre = box.isEmpty() ? Vec3::Zero() : Vec3(box.center());
    const Vec3 half = Vec3::Constant(0.5 * settings.minimumSize);
    const Box3 small(centre - half, centre + half);
    for (int corner = 0; corner < 8; ++corner) points.push_back(small.corner(static_cast<Box3::CornerType>(corner)));
    box.extend(small);
  }

  RenderCamera camera;
  camera.fovDegrees = settings.fovDegrees;
  const Vec3 forward = settings.viewDirection.normalized();
  camera.up = std::abs(forward.y()) > 0.999 ? Vec3(0.0, 0.0, -1.0) : Vec3(0.0, 1.0, 0.0);
  const Vec3 right = forward.cross(camera.up).normalized();
  const Vec3 cameraUp = right.cross(forward);
  const double tanHalfY = std::tan(0.5 * degreesToRadians(settings.fovDegrees));
  const double tanHalfX = tanHalfY * aspect;
  // With the camera at target - distance * forward, a point p is at depth distance + (p - target).forward and
  // lateral offsets (p - target).right / .up: it is inside the view when both offsets fit the half-angles.
  auto fitDistance = [&](const Vec3& target) {
    double distance = 0.0;
    for (const Vec3& p : points) {
      const Vec3 offset = p - target;
      const double along = offset.dot(forward);
      distance = std::max(distance, std::abs(offset.dot(right)) / tanHalfX - along);
      distance = std::max(distance, std::abs(offset.dot(cameraUp)) / tanHalfY - along);
    }
    return std::max(distance, 1e-3);
  };
  // Start at the box centre, then slide the target sideways so the projected extents are centred (a few
  // rounds: each slide changes the depths a little).
  Vec3 target = box.center();
  for (int round = 0; round < 4; ++round) {
    const double distance = fitDistance(target);
    double minX = 1e300, maxX = -1e300, minY = 1e300, maxY = -1e300;
    for (const Vec3& p : points) {
      const Vec3 offset = p - target;
      const double depth = std::max(distance + offset.dot(forward), 1e-9);
      const double x = offset.dot(right) / depth;
      const double y = offset.dot(cameraUp) / depth;
      minX = std::min(minX, x), maxX = std::max(maxX, x), minY = std::min(minY, y), maxY = std::max(maxY, y);
    }
    target += distance * (0.5 * (minX + maxX) * right + 0.5 * (minY + maxY) * cameraUp);
  }
  camera.target = target;
  camera.eye = target - settings.margin * fitDistance(target) * forward;
  camera.validate();
  return camera;
}

RenderCamera frameBox(const Box3& worldBox, double aspect, const CameraFramingSettings& settings) {
  std::vector<Vec3> corners;
  if (!worldBox.isEmpty()) {
    for (int corner = 0; corner < 8; ++corner)
      corners.push_back(worldBox.corner(static_cast<Box3::CornerType>(corner)));
  }
  return framePoints(corners, aspect, settings);
}

}  // namespace sdfccd::render
