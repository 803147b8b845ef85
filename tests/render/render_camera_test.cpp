/// @file
/// @brief RenderCamera: the pixel projection agrees with the GL matrices; framing fits boxes; bad cameras fail.
#include "sdfccd/render/render_camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "sdfccd/error.h"

namespace sdfccd::render {
namespace {

TEST(RenderCamera, ProjectionAgreesWithTheGlMatrices) {
  RenderCamera camera;
  camera.eye = Vec3(1.0, 2.0, 3.0);
  camera.target = Vec3(-0.5, 0.2, 0.1);
  camera.fovDegrees = 50.0;
  const int width = 640, height = 360;
  const Eigen::Matrix4d projection = camera.projection(static_cast<double>(width) / height, 0.1, 100.0);
  const Rigid viewFromWorld = camera.viewFromWorld();
  for (const Vec3& p : {Vec3(0.0, 0.0, 0.0), Vec3(0.3, -0.2, 0.5), Vec3(-1.0, 1.0, -1.0)}) {
    const Eigen::Vector4d clip = projection * (viewFromWorld * p).homogeneous();
    const Eigen::Vector2d ndc = clip.head<2>() / clip.w();
    const PixelProjection projected = projectToPixel(camera, p, width, height);
    ASSERT_TRUE(projected.inFront);
    EXPECT_NEAR(projected.pixel.x(), 0.5 * (ndc.x() + 1.0) * width, 1e-9);
    EXPECT_NEAR(projected.pixel.y(), 0.5 * (1.0 - ndc.y()) * height, 1e-9);
  }
  // The target projects to the image centre; a point behind the eye is not in front.
  const PixelProjection centre = projectToPixel(camera, camera.target, width, height);
  EXPECT_NEAR(centre.pixel.x(), width / 2.0, 1e-9);
  EXPECT_NEAR(centre.pixel.y(), height / 2.0, 1e-9);
  EXPECT_FALSE(projectToPixel(camera, camera.eye + (camera.eye - camera.target), width, height).inFront);
  // Up in the world is up in the image.
  EXPECT_LT(projectToPixel(camera, camera.target + Vec3(0.0, 0.1, 0.0), width, height).pixel.y(), height / 2.0);
}

TEST(RenderCamera, FramingFitsEveryCornerWithItsMargin) {
  const Box3 box(Vec3(-3.0, 0.0, -1.0), Vec3(2.0, 4.0, 0.5));
  for (double aspect : {0.5, 1.0, 16.0 / 9.0}) {
    CameraFramingSettings settings;
    const RenderCamera camera = frameBox(box, aspect, settings);
    const int height = 400;
    const int width = static_cast<int>(aspect * height);
    double largest = 0.0;  // how close a corner comes to the border, in fractions of the half-size
    for (int corner = 0; corner < 8; ++corner) {
      const PixelProjection p =
          projectToPixel(camera, box.corner(static_cast<Box3::CornerType>(corner)), width, height);
      ASSERT_TRUE(p.inImage) << "aspect " << aspect << " corner " << corner;
      largest = std::max(largest, std::abs(p.pixel.x() - width / 2.0) / (width / 2.0));
      largest = std::max(largest, std::abs(p.pixel.y() - height / 2.0) / (height / 2.0));
    }
    EXPECT_GT(largest, 0.75) << "the box fills the image (tight fit)";
    EXPECT_GT(camera.eye.y(), box.max().y()) << "seen from above";
  }
  // An empty box is framed as a small box at the origin rather than failing.
  EXPECT_NO_THROW(frameBox(Box3(), 1.0));
}

TEST(RenderCamera, SmallScenesFillTheImageWithASmallMinimumSize) {
  // A 1 cm cube (a haptic scene's size): with the default minimum (0.1 m) it is framed as a 0.1 m box and stays
  // small in the image; with minimumSize 1 mm it is fitted tightly, as large boxes are.
  std::vector<Vec3> corners;
  const Box3 box(Vec3(0.2, 0.3, 0.4), Vec3(0.21, 0.31, 0.41));
  for (int corner = 0; corner < 8; ++corner) corners.push_back(box.corner(static_cast<Box3::CornerType>(corner)));
  const auto largestOffset = [&](const RenderCamera& camera) {
    double largest = 0.0;  // how close a corner comes to the border, in fractions of the half-size
    for (const Vec3& c : corners) {
      const PixelProjection p = projectToPixel(camera, c, 400, 400);
      EXPECT_TRUE(p.inImage);
      largest = std::max(largest, std::max(std::abs(p.pixel.x() - 200.0), std::abs(p.pixel.y() - 200.0)) / 200.0);
    }
    return largest;
  };
  CameraFramingSettings small;
  small.minimumSize = 1e-3;
  EXPECT_LT(largestOffset(framePoints(corners, 1.0)), 0.4);
  EXPECT_GT(largestOffset(framePoints(corners, 1.0, small)), 0.75);
  small.minimumSize = 0.0;
  EXPECT_THROW(framePoints(corners, 1.0, small), Error);
}

TEST(RenderCamera, BadCamerasAreClearErrors) {
  RenderCamera camera;
  camera.fovDegrees = 0.0;
  EXPECT_THROW(camera.validate(), Error);
  camera.fovDegrees = 40.0;
  camera.up = (camera.target - camera.eye);  // up along the view direction
  EXPECT_THROW(camera.validate(), Error);
  camera.up = Vec3(0.0, 1.0, 0.0);
  camera.eye.x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(camera.validate(), Error);
  EXPECT_THROW(frameBox(Box3(Vec3::Zero(), Vec3::Ones()), -1.0), Error);
}

}  // namespace
}  // namespace sdfccd::render
