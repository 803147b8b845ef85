/// @file
/// @brief RenderCamera: look-at and perspective matrices, projection to pixels, automatic framing.
#include "sdfccd/render/render_camera.h"

#include <algorithm>
#include <cmath>

#include "sdfccd/error.h"

namespace sdfccd::render {

namespace {

constexpr double kPi = 3.14159265358979323846;

double degreesToRadians(double degrees) { return degrees * kPi / 180.0; }

bool isFinite(const Vec3& v) { return v.allFinite(); }

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
  const Vec3 back = (eye - target).normalized();        // camera +z (it looks down -z)
  const Vec3 right = up.cross(back).normalized();        // camera +x
  const Vec3 cameraUp = back.cross(right);               // camera +y
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
  result.inImage = result.pixel.x() >= 0.0 && result.pixel.x() < width && result.pixel.y() >= 0.0 &&
                   result.pixel.y() < height;
  return result;
}

RenderCamera frameBox(const Box3& worldBox, double aspect, const CameraFramingSettings& settings) {
  if (!(aspect > 0.0) || !std::isfinite(aspect)) throw Error("camera framing: bad image aspect ratio");
  if (!settings.viewDirection.allFinite() || settings.viewDirection.norm() <= 1e-12) {
    throw Error("camera framing: the view direction must be finite and non-zero");
  }
  if (!(settings.margin >= 1.0) || !std::isfinite(settings.margin)) throw Error("camera framing: margin must be >= 1");
  Box3 box = worldBox;
  if (box.isEmpty()) box = Box3(Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05));
  if (!box.min().allFinite() || !box.max().allFinite()) throw Error("camera framing: the scene bounds are not finite");
  const Vec3 centre = box.center();
  const Vec3 halfSize = (0.5 * box.sizes()).cwiseMax(0.05);
  box = Box3(centre - halfSize, centre + halfSize);

  RenderCamera camera;
  camera.fovDegrees = settings.fovDegrees;
  camera.target = centre;
  const Vec3 forward = settings.viewDirection.normalized();
  camera.up = std::abs(forward.y()) > 0.999 ? Vec3(0.0, 0.0, -1.0) : Vec3(0.0, 1.0, 0.0);
  const Vec3 right = forward.cross(camera.up).normalized();
  const Vec3 cameraUp = right.cross(forward);
  const double tanHalfY = std::tan(0.5 * degreesToRadians(settings.fovDegrees));
  const double tanHalfX = tanHalfY * aspect;
  // With the camera at centre - distance * forward, a corner p is at depth distance + (p - centre).forward and
  // lateral offsets (p - centre).right / .up: it is inside the view when both offsets fit the half-angles.
  double distance = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 offset = box.corner(static_cast<Box3::CornerType>(corner)) - centre;
    const double along = offset.dot(forward);
    distance = std::max(distance, std::abs(offset.dot(right)) / tanHalfX - along);
    distance = std::max(distance, std::abs(offset.dot(cameraUp)) / tanHalfY - along);
  }
  distance = std::max(distance * settings.margin, 1e-3);
  camera.eye = centre - distance * forward;
  camera.validate();
  return camera;
}

}  // namespace sdfccd::render
