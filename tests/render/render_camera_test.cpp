/// @file
/// @brief RenderCamera: the pixel projection agrees with the GL matrices; framing fits boxes; bad cameras fail.
#include "sdfccd/render/render_camera.h"

#include <gtest/gtest.h>

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
