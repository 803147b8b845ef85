/// @file
/// @brief RenderCamera: a pinhole camera (eye, target, up, vertical field of view) and automatic framing.
///
/// @details The same matrices drive OpenGL and the tests: projectToPixel() gives the continuous pixel
/// coordinates (x to the right, y down, pixel (i, j) covers [i, i+1) x [j, j+1)) where the renderer puts a world
/// point, so a test can check an image against an analytic projection. Automatic framing looks at the bodies'
/// world box from a fixed direction (front, right and above, so the ground is seen slightly from above) and
/// backs off until every corner of the box is inside the image with a margin.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "sdfccd/math_types.h"

namespace sdfccd::render {

/// A pinhole camera. The field of view is vertical; the horizontal one follows from the image's aspect ratio.
struct RenderCamera {
  Vec3 eye = Vec3(0.0, 1.0, 5.0);     ///< camera position (m, world)
  Vec3 target = Vec3(0.0, 0.0, 0.0);  ///< point looked at (m, world)
  Vec3 up = Vec3(0.0, 1.0, 0.0);      ///< approximate up direction (world); need not be orthogonal to the view
  double fovDegrees = 40.0;           ///< vertical field of view (degrees, in (0, 179))

  /// Throws sdfccd::Error unless eye/target/up are finite, eye != target, up is not along the view
  /// direction, and the field of view is in (0, 179) degrees.
  void validate() const;
  /// The rigid transform from world to camera coordinates (OpenGL convention: the camera looks down -z,
  /// +y is up in the image).
  Rigid viewFromWorld() const;
  /// The OpenGL perspective projection for an image of `aspect` = width / height and the clip range (m).
  Eigen::Matrix4d projection(double aspect, double nearDistance, double farDistance) const;
};

/// Where a world point lands in an image.
struct PixelProjection {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  ///< continuous pixel coordinates (x right, y down)
  double depth = 0.0;                               ///< distance in front of the camera along the view axis (m)
  bool inFront = false;                             ///< depth > 0 (otherwise `pixel` is meaningless)
  bool inImage = false;                             ///< inFront and inside [0, width) x [0, height)
};

/// Projects `pointInWorld` for an image of width x height pixels (clip planes do not matter here).
PixelProjection projectToPixel(const RenderCamera& camera, const Vec3& pointInWorld, int width, int height);

/// How automatic framing chooses the camera.
struct CameraFramingSettings {
  Vec3 viewDirection = Vec3(-0.55, -0.42, -1.0);  ///< direction the camera looks along (world; normalised)
  double fovDegrees = 35.0;                       ///< vertical field of view (degrees)
  double margin = 1.12;                           ///< distance factor beyond the tight fit (>= 1)
  /// Points spanning less than this on every axis are framed as a box of this size (m, > 0): 0.1 m suits the
  /// simulation scenes; haptic scenes, centimetres across, pass a smaller one.
  double minimumSize = 0.1;
};

/// A camera that sees every point of `pointsInWorld` in an image of aspect = width / height, looking along
/// settings.viewDirection; the target is moved sideways so the points' projection is centred. Points spanning
/// less than settings.minimumSize (0.1 m) are framed as a box of that size. Throws sdfccd::Error for non-finite points
/// or bad settings.
RenderCamera framePoints(const std::vector<Vec3>& pointsInWorld, double aspect,
                         const CameraFramingSettings& settings = {});

/// A camera that sees all of `worldBox` in an image of aspect = width / height. An empty or degenerate box is
/// framed as a box of at least 0.1 m. Throws sdfccd::Error for a non-finite box or bad settings.
RenderCamera frameBox(const Box3& worldBox, double aspect, const CameraFramingSettings& settings = {});

}  // namespace sdfccd::render
