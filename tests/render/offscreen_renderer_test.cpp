/// @file
/// @brief OffscreenRenderer against analytic projections: horizon, silhouette areas, contact pixels, determinism.
#include "sdfccd/render/offscreen_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>

#include "render/test_meshes.h"
#include "sdfccd/error.h"
#include "sdfccd/render/png_file.h"

namespace sdfccd::render {
namespace {

/// Saved next to the test binary for looking at by eye (not part of any assertion).
void keepForInspection(const RgbImage& image, const std::string& name) {
  const char* folder = std::getenv("SDFCCD_RENDER_TEST_OUT");
  if (folder != nullptr) writePng(std::string(folder) + "/" + name + ".png", image);
}

bool isRed(const std::uint8_t* p) {
  return p[0] > p[1] + 40 && p[0] > p[2] + 40;
}

int countPixels(const RgbImage& image, bool (*predicate)(const std::uint8_t*)) {
  int count = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) count += predicate(image.at(x, y)) ? 1 : 0;
  return count;
}

RenderMesh redBody(std::shared_ptr<TriangleMesh> mesh, const Vec3& position, double scale = 1.0) {
  RenderMesh body;
  body.name = "probe";
  body.mesh = std::move(mesh);
  body.worldFromBody = Rigid::Identity();
  body.worldFromBody.translation() = position;
  body.scale = scale;
  body.color = Color(0.9f, 0.1f, 0.1f);
  return body;
}

RenderSettings plainSettings(int width, int height) {
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.supersample = 1;
  settings.shading = Shading::Flat;
  settings.background = Color(0.0f, 0.0f, 0.0f);
  return settings;
}

// Pixels that are not black (the plain settings' background).
int litPixels(const RgbImage& image) {
  return countPixels(image, [](const std::uint8_t* p) { return p[0] + p[1] + p[2] > 0; });
}

// The camera 5 units up the z axis looking at the origin, 40 degrees of vertical field of view.
RenderCamera onAxisCamera() {
  RenderCamera camera;
  camera.eye = Vec3(0.0, 0.0, 5.0);
  camera.target = Vec3::Zero();
  camera.fovDegrees = 40.0;
  return camera;
}

// The focal length in pixels of `camera` in an image `height` pixels high.
double focalPixels(const RenderCamera& camera, int height) {
  return 0.5 * height / std::tan(0.5 * camera.fovDegrees * kPi / 180.0);
}

// A body above the ground, seen by a camera looking horizontally: the horizon is the middle row, the body is
// entirely above it at its projected place, the ground entirely below it.
TEST(OffscreenRenderer, BodyAboveGroundAppearsAboveTheHorizonWhereProjected) {
  RenderScene scene;
  const double radius = 0.5;
  const Vec3 centre(0.0, 2.5, 0.0);
  scene.meshes.push_back(redBody(test::makeIcosphere(4), centre, radius));
  scene.ground = RenderGround{};
  RenderCamera camera;
  camera.eye = Vec3(0.0, 1.0, 8.0);
  camera.target = Vec3(0.0, 1.0, 0.0);
  camera.fovDegrees = 40.0;
  scene.camera = camera;
  RenderSettings settings = plainSettings(320, 240);
  settings.background = Color(0.5f, 0.7f, 1.0f);

  OffscreenRenderer renderer;
  const RgbImage image = renderer.render(scene, settings);
  keepForInspection(image, "horizon");

  int minX = image.width, maxX = -1, minY = image.height, maxY = -1;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (!isRed(image.at(x, y))) continue;
      minX = std::min(minX, x), maxX = std::max(maxX, x), minY = std::min(minY, y), maxY = std::max(maxY, y);
    }
  }
  ASSERT_GE(maxX, 0) << "the body is not in the picture";
  const int horizonRow = image.height / 2;
  EXPECT_LT(maxY, horizonRow);
  // Analytic silhouette: a circle around the projected centre (the view axis is nearly through it).
  const PixelProjection projected = projectToPixel(camera, centre, image.width, image.height);
  const double distance = (centre - camera.eye).norm();
  const double focal = focalPixels(camera, image.height);
  const double radiusPixels = focal * std::tan(std::asin(radius / distance));
  EXPECT_NEAR(0.5 * (minX + maxX + 1), projected.pixel.x(), 1.5);
  EXPECT_NEAR(0.5 * (minY + maxY + 1), projected.pixel.y(), 1.5);
  EXPECT_NEAR(0.5 * (maxX - minX + 1), radiusPixels, 2.0);
  EXPECT_NEAR(0.5 * (maxY - minY + 1), radiusPixels, 2.5);  // off-axis: slightly stretched vertically

  // Sky just above the horizon, ground just below it (away from the body), on the whole width.
  const std::uint8_t* sky = image.at(5, horizonRow - 3);
  const std::uint8_t* ground = image.at(5, horizonRow + 3);
  EXPECT_GT(sky[2], 240);  // the background (0.5, 0.7, 1.0)
  EXPECT_NEAR(sky[0], 128, 2);
  EXPECT_LT(ground[2], 230);  // lit grey, not sky blue
  EXPECT_NEAR(ground[0], ground[2], 12);
  for (int x = 0; x < image.width; ++x) {
    EXPECT_EQ(maxChannelDifference(RgbImage(1, 1, sky[0], sky[1], sky[2]),
                                   RgbImage(1, 1, image.at(x, horizonRow - 3)[0], image.at(x, horizonRow - 3)[1],
                                            image.at(x, horizonRow - 3)[2])),
              0)
        << "column " << x << " above the horizon is not sky";
  }
}

// A body sunk entirely below the ground is hidden by it when seen from above: a picture of a tunnelled body
// shows no body.
TEST(OffscreenRenderer, BodyBelowGroundIsHiddenFromAbove) {
  RenderScene scene;
  scene.meshes.push_back(redBody(test::makeIcosphere(3), Vec3(0.0, -1.0, 0.0), 0.5));
  scene.ground = RenderGround{};
  RenderCamera camera;
  camera.eye = Vec3(0.0, 3.0, 4.0);
  camera.target = Vec3(0.0, -1.0, 0.0);
  scene.camera = camera;
  OffscreenRenderer renderer;
  const RgbImage image = renderer.render(scene, plainSettings(200, 150));
  EXPECT_EQ(countPixels(image, isRed), 0);
  // Lifted above the ground, the same body is in the picture.
  scene.meshes[0].worldFromBody.translation().y() = 0.6;
  EXPECT_GT(countPixels(renderer.render(scene, plainSettings(200, 150)), isRed), 500);
}

// A sphere on the view axis projects to a disc of radius f tan(asin(r / d)).
TEST(OffscreenRenderer, SphereSilhouetteMatchesProjectedArea) {
  RenderScene scene;
  const double radius = 1.0;
  scene.meshes.push_back(redBody(test::makeIcosphere(5), Vec3::Zero(), radius));
  const RenderCamera camera = onAxisCamera();
  scene.camera = camera;
  const RenderSettings settings = plainSettings(400, 400);
  OffscreenRenderer renderer;
  const RgbImage image = renderer.render(scene, settings);
  keepForInspection(image, "sphere");
  const double focal = focalPixels(camera, settings.height);
  const double discRadius = focal * std::tan(std::asin(radius / 5.0));
  const double expected = kPi * discRadius * discRadius;
  const int counted = litPixels(image);
  EXPECT_NEAR(counted, expected, 0.01 * expected) << "disc radius " << discRadius << " px";
}

// A cube facing the camera on its axis shows only its front face: a square of side f * 2a / (d - a).
TEST(OffscreenRenderer, BoxSilhouetteMatchesProjectedArea) {
  RenderScene scene;
  const double half = 0.8;
  scene.meshes.push_back(redBody(test::makeBox(Vec3(half, half, half)), Vec3::Zero()));
  const RenderCamera camera = onAxisCamera();
  scene.camera = camera;
  const RenderSettings settings = plainSettings(400, 300);
  OffscreenRenderer renderer;
  const RgbImage image = renderer.render(scene, settings);
  const double focal = focalPixels(camera, settings.height);
  const double side = focal * 2.0 * half / (5.0 - half);
  const int counted = litPixels(image);
  EXPECT_NEAR(counted, side * side, 0.01 * side * side) << "side " << side << " px";
  // Rotated 45 degrees about the view axis, the front face is the same square turned: same area.
  scene.meshes[0].worldFromBody.linear() = Eigen::AngleAxisd(kPi / 4.0, Vec3::UnitZ()).toRotationMatrix();
  const int turned = litPixels(renderer.render(scene, settings));
  EXPECT_NEAR(turned, side * side, 0.015 * side * side);
}

// Contacts are drawn in the depth colour where they project, also when a body hides them; plain points in
// their own colour; contacts can be depth tested instead.
TEST(OffscreenRenderer, ContactsAreHighlightedWhereTheyAre) {
  RenderScene scene;
  scene.meshes.push_back(redBody(test::makeIcosphere(3), Vec3::Zero(), 1.0));
  RenderCamera camera;
  camera.eye = Vec3(0.0, 0.0, 6.0);
  camera.target = Vec3::Zero();
  scene.camera = camera;
  RenderPointSet points;
  points.pointsInWorld = {Vec3(1.8, 0.9, 0.0),    // plain point beside the sphere
                          Vec3(-1.8, -0.9, 0.0),  // shallow contact beside the sphere
                          Vec3(0.3, 0.2, -1.2),   // deep contact behind the sphere (hidden by it)
                          Vec3(-0.4, 0.5, 0.6)};  // plain point inside the sphere (hidden)
  points.depths = {0.0, 0.001, 0.004, -0.01};
  points.maxDepth = 0.004;
  points.pointSize = 5.0f;
  points.contactPointSize = 7.0f;
  scene.pointSets.push_back(points);
  const RenderSettings settings = plainSettings(320, 240);
  OffscreenRenderer renderer;
  const RgbImage image = renderer.render(scene, settings);
  keepForInspection(image, "contacts");

  auto expectColourAt = [&](const RgbImage& picture, const Vec3& pointInWorld, const Color& colour) {
    const PixelProjection projected = projectToPixel(camera, pointInWorld, picture.width, picture.height);
    ASSERT_TRUE(projected.inImage);
    const std::uint8_t* p = picture.at(static_cast<int>(projected.pixel.x()), static_cast<int>(projected.pixel.y()));
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(p[c], std::lround(255.0f * colour[c]), 2) << "channel " << c << " at " << projected.pixel.transpose();
    }
  };
  expectColourAt(image, points.pointsInWorld[0], points.color);
  expectColourAt(image, points.pointsInWorld[1], depthColor(0.001, 0.004, points.color));
  expectColourAt(image, points.pointsInWorld[2], depthColor(0.004, 0.004, points.color));
  // The ramp runs from yellow to red: the deep contact is red, the shallow one orange-yellow.
  EXPECT_GT(depthColor(0.001, 0.004, points.color).y(), 0.6f);
  EXPECT_LT(depthColor(0.004, 0.004, points.color).y(), 0.05f);
  // The plain point inside the sphere is hidden: the sphere's own colour shows there.
  const PixelProjection hidden = projectToPixel(camera, points.pointsInWorld[3], image.width, image.height);
  EXPECT_TRUE(isRed(image.at(static_cast<int>(hidden.pixel.x()), static_cast<int>(hidden.pixel.y()))));

  // Depth-tested contacts: the one behind the sphere disappears, the one beside it stays.
  scene.pointSets[0].contactsOnTop = false;
  const RgbImage tested = renderer.render(scene, settings);
  const PixelProjection behind = projectToPixel(camera, points.pointsInWorld[2], tested.width, tested.height);
  EXPECT_TRUE(isRed(tested.at(static_cast<int>(behind.pixel.x()), static_cast<int>(behind.pixel.y()))));
  expectColourAt(tested, points.pointsInWorld[1], depthColor(0.001, 0.004, points.color));
}

RenderScene twoBodiesOnGround() {
  RenderScene scene;
  RenderMesh sphere = redBody(test::makeIcosphere(3), Vec3(-0.6, 0.5, 0.0), 0.5);
  RenderMesh box = redBody(test::makeBox(Vec3(0.3, 0.2, 0.4)), Vec3(0.7, 0.2, 0.1));
  box.worldFromBody.linear() = Eigen::AngleAxisd(0.4, Vec3(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  box.color = Color(0.3f, 0.6f, 0.9f);
  scene.meshes = {sphere, box};
  scene.ground = RenderGround{};
  RenderPointSet points;
  points.pointsInWorld = {Vec3(-0.6, 0.0, 0.0), Vec3(0.7, 0.0, 0.1), Vec3(-0.6, 1.0, 0.0)};
  points.depths = {0.002, 0.0005, 0.0};
  scene.pointSets.push_back(points);
  return scene;
}

TEST(OffscreenRenderer, SameInputGivesSameImage) {
  const RenderScene scene = twoBodiesOnGround();
  RenderSettings settings;
  settings.width = 320;
  settings.height = 200;
  settings.supersample = 2;
  OffscreenRenderer first;
  OffscreenRenderer second;
  const RgbImage a = first.render(scene, settings);
  const RgbImage b = second.render(scene, settings);
  const RgbImage c = first.render(scene, settings);
  keepForInspection(a, "two_bodies");
  EXPECT_LE(maxChannelDifference(a, b), 1);
  EXPECT_LE(maxChannelDifference(a, c), 1);
  // Something was drawn: sky, ground and both bodies.
  EXPECT_GT(countPixels(a, isRed), 200);
  EXPECT_GT(countPixels(a, [](const std::uint8_t* p) { return p[2] > p[0] + 60; }), 200);
  // A changed pose changes the picture.
  RenderScene moved = scene;
  moved.meshes[1].worldFromBody.translation().x() += 0.2;
  EXPECT_GT(maxChannelDifference(a, first.render(moved, settings)), 50);
}

TEST(OffscreenRenderer, AutomaticFramingShowsEveryBodyAndTheGroundUnderThem) {
  RenderScene scene = twoBodiesOnGround();
  scene.meshes[0].worldFromBody.translation() = Vec3(-3.0, 2.0, 1.0);  // spread the bodies out
  RenderSettings settings = plainSettings(240, 160);
  settings.background = Color(0.92f, 0.94f, 0.97f);
  const RenderCamera camera = OffscreenRenderer::cameraFor(scene, settings);
  for (const RenderMesh& body : scene.meshes) {
    const Box3 box = worldBounds(body);
    for (int corner = 0; corner < 8; ++corner) {
      const PixelProjection projected =
          projectToPixel(camera, box.corner(static_cast<Box3::CornerType>(corner)), settings.width, settings.height);
      EXPECT_TRUE(projected.inImage) << body.name << " corner " << corner << " at " << projected.pixel.transpose();
    }
  }
  EXPECT_GT(camera.eye.y(), 2.0);  // seen from above
  OffscreenRenderer renderer;
  const RgbImage image = renderer.render(scene, settings);
  keepForInspection(image, "auto_framing");
  EXPECT_GT(countPixels(image, isRed), 100);
}

TEST(OffscreenRenderer, BadInputIsAClearError) {
  OffscreenRenderer renderer;
  const RenderSettings settings = plainSettings(64, 48);
  auto expectError = [&](const RenderScene& scene, const RenderSettings& s, const std::string& fragment) {
    try {
      renderer.render(scene, s);
      ADD_FAILURE() << "no error for: " << fragment;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  RenderScene missing;
  missing.meshes.push_back(redBody(nullptr, Vec3::Zero()));
  missing.meshes[0].name = "bunny7";
  expectError(missing, settings, "body 'bunny7' has no mesh");

  RenderScene empty;
  empty.meshes.push_back(redBody(std::make_shared<TriangleMesh>(), Vec3::Zero()));
  expectError(empty, settings, "empty mesh");

  RenderScene nanPose = twoBodiesOnGround();
  nanPose.meshes[1].worldFromBody.translation().x() = std::numeric_limits<double>::quiet_NaN();
  expectError(nanPose, settings, "non-finite pose");

  RenderScene badScale = twoBodiesOnGround();
  badScale.meshes[0].scale = -1.0;
  expectError(badScale, settings, "scale");

  RenderScene badDepths = twoBodiesOnGround();
  badDepths.pointSets[0].depths.pop_back();
  expectError(badDepths, settings, "depths for");

  RenderScene badCamera = twoBodiesOnGround();
  badCamera.camera = RenderCamera{};
  badCamera.camera->target = badCamera.camera->eye;
  expectError(badCamera, settings, "eye and target");

  RenderSettings tiny = settings;
  tiny.width = 0;
  expectError(twoBodiesOnGround(), tiny, "image size");
  RenderSettings huge = settings;
  huge.supersample = 1000;
  expectError(twoBodiesOnGround(), huge, "supersampling");
}

}  // namespace
}  // namespace sdfccd::render
