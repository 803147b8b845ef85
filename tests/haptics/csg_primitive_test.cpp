/// @file
/// @brief The CSG primitives of haptic scenes (haptic_scene.h): box, cylinder along any axis, capsule; their exact
/// signed distances against closed forms, their bounds, the sampled grid, and the scene reader's errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/haptics/haptic_scene.h"

namespace sdfccd::haptics {
namespace {

CsgPrimitive capsule(const Vec3& from, const Vec3& to, double radius) {
  CsgPrimitive p;
  p.kind = CsgPrimitive::Kind::Capsule;
  p.center = from;
  p.end = to;
  p.radius = radius;
  return p;
}

CsgPrimitive cylinder(const Vec3& center, const Vec3& axis, double radius, double halfHeight) {
  CsgPrimitive p;
  p.kind = CsgPrimitive::Kind::Cylinder;
  p.center = center;
  p.axis = axis.normalized();
  p.radius = radius;
  p.halfHeight = halfHeight;
  return p;
}

TEST(CsgPrimitive, CapsuleDistanceIsTheSegmentDistanceMinusTheRadius) {
  const CsgPrimitive c = capsule(Vec3(-1, 0, 0), Vec3(1, 0, 0), 0.25);
  EXPECT_NEAR(c.signedDistance(Vec3(0.3, 2.0, 0.0)), 1.75, 1e-15);        // beside the segment
  EXPECT_NEAR(c.signedDistance(Vec3(0.3, 0.1, 0.0)), -0.15, 1e-15);       // inside
  EXPECT_NEAR(c.signedDistance(Vec3(4.0, 4.0, 0.0)), 5.0 - 0.25, 1e-15);  // past the end: distance to (1, 0, 0)
  EXPECT_NEAR(c.signedDistance(Vec3(-1.0, 0.0, 0.0)), -0.25, 1e-15);      // on the segment's end
  const CsgPrimitive ball = capsule(Vec3(1, 2, 3), Vec3(1, 2, 3), 0.5);   // a zero-length segment: a sphere
  EXPECT_NEAR(ball.signedDistance(Vec3(1, 2, 5)), 1.5, 1e-15);
  // An inclined capsule: the distance is invariant under moving along it.
  const CsgPrimitive inclined = capsule(Vec3(0, 0, 0), Vec3(3, 4, 0), 0.1);
  const Vec3 normal(-0.8, 0.6, 0.0);
  for (double s : {0.0, 1.0, 2.5, 5.0})
    EXPECT_NEAR(inclined.signedDistance(s * Vec3(0.6, 0.8, 0.0) + 0.7 * normal), 0.6, 1e-14) << s;
}

TEST(CsgPrimitive, CylinderAlongAnyAxisMatchesTheYCylinderRotated) {
  // The same cylinder along y and along x: distances at mirrored points (x <-> y) are equal.
  const CsgPrimitive alongY = cylinder(Vec3::Zero(), Vec3::UnitY(), 0.5, 2.0);
  const CsgPrimitive alongX = cylinder(Vec3::Zero(), Vec3::UnitX(), 0.5, 2.0);
  for (const Vec3& p : {Vec3(0.1, 0.2, 0.3), Vec3(3.0, 0.2, 0.1), Vec3(0.2, 2.5, 0.9), Vec3(1.0, 1.0, 1.0)})
    EXPECT_NEAR(alongX.signedDistance(Vec3(p.y(), p.x(), p.z())), alongY.signedDistance(p), 1e-15);
  // Closed forms: side, cap, rim (corner) and inside, for an inclined axis.
  const Vec3 axis = Vec3(1, 1, 0).normalized();
  const Vec3 side = Vec3(1, -1, 0).normalized();
  const CsgPrimitive inclined = cylinder(Vec3(1, 1, 1), axis, 0.5, 2.0);
  EXPECT_NEAR(inclined.signedDistance(Vec3(1, 1, 1) + 0.5 * axis + 1.5 * side), 1.0, 1e-14);
  EXPECT_NEAR(inclined.signedDistance(Vec3(1, 1, 1) + 3.0 * axis + 0.2 * side), 1.0, 1e-14);
  EXPECT_NEAR(inclined.signedDistance(Vec3(1, 1, 1) + 5.0 * axis + 4.5 * side), 5.0, 1e-14);  // 3-4-5 off the rim
  EXPECT_NEAR(inclined.signedDistance(Vec3(1, 1, 1) + 1.9 * axis + 0.1 * side), -0.1, 1e-14);
}

TEST(CsgPrimitive, BoundsHoldThePrimitiveAndBadSizesThrow) {
  const CsgPrimitive inclined = cylinder(Vec3(1, 0, 0), Vec3(1, 1, 0), 0.5, 2.0);
  const Box3 box = inclined.bounds();
  // Every point of the surface sampled round both rims lies in the box, and the box touches the rims.
  const Vec3 a = inclined.axis, u = Vec3(1, -1, 0).normalized(), v = Vec3::UnitZ();
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (int end = -1; end <= 1; end += 2) {
    for (int k = 0; k < 3600; ++k) {
      const double t = 2.0 * M_PI * k / 3600.0;
      const Vec3 p = inclined.center + end * 2.0 * a + 0.5 * (std::cos(t) * u + std::sin(t) * v);
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  EXPECT_LT((box.min() - lo).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((box.max() - hi).cwiseAbs().maxCoeff(), 1e-6);
  const Box3 capsuleBox = capsule(Vec3(0, 0, 0), Vec3(1, -2, 3), 0.5).bounds();
  EXPECT_LT((capsuleBox.min() - Vec3(-0.5, -2.5, -0.5)).norm(), 1e-15);
  EXPECT_LT((capsuleBox.max() - Vec3(1.5, 0.5, 3.5)).norm(), 1e-15);
  EXPECT_THROW(capsule(Vec3::Zero(), Vec3::UnitX(), 0.0).bounds(), Error);
  CsgPrimitive notUnit = inclined;
  notUnit.axis = Vec3(1, 1, 0);
  EXPECT_THROW(notUnit.bounds(), Error);
}

TEST(CsgPrimitive, SampledWireOfTwoCellsHasItsExactDistanceAtTheNodes) {
  // The landing gear's wire: a capsule of radius one cell along x, sampled on the grid.
  CsgObstacle csg;
  csg.spacing = 0.25;
  csg.solids.push_back(capsule(Vec3(-4, 0, 0), Vec3(4, 0, 0), 0.25));
  csg.solids.push_back(cylinder(Vec3(0, 0, 3), Vec3(0, 0, 1), 0.5, 1.0));  // a strut along z
  const std::shared_ptr<const SdfGrid> grid = sampleCsgObstacle(csg);
  const GridField field(grid);
  // The grid holds both solids (their boxes plus the padding) and reproduces the CSG value at its nodes.
  EXPECT_LE(grid->origin().z(), -0.25 - 3 * 0.25 + 1e-12);
  for (const Vec3& p : {Vec3(0.0, 0.0, 0.0), Vec3(1.0, 0.5, 0.25), Vec3(0.0, 0.0, 3.5), Vec3(-4.25, 0.0, 0.0)}) {
    const Vec3 index = (p - grid->origin()) / grid->spacing();
    ASSERT_NEAR(index.x(), std::round(index.x()), 1e-9);  // the probes are nodes
    EXPECT_NEAR(field.distance(p), csg.signedDistance(p), 1e-6) << p.transpose();
  }
  EXPECT_NEAR(field.distance(Vec3(1.0, 0.0, 0.0)), -0.25, 1e-6);  // the wire's axis: one cell inside
}

std::string writeSceneFile(const std::string& solids) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("sdfccd_csg_scene_" + std::to_string(::getpid()) + ".json");
  std::ofstream(path) << R"({"obstacle": {"spacing": 0.001, "solids": [)" << solids
                      << R"(]}, "shell": {"shape": "sphere", "radius": 0.002, "subdivisions": 1, "points": 20},
      "start": {"position": [0, 0.05, 0]}, "script": [{"t": 0, "position": [0, 0.05, 0]}]})";
  return path.string();
}

void expectSceneError(const std::string& solids, const std::string& key) {
  const std::string path = writeSceneFile(solids);
  try {
    (void)loadHapticScene(path);
    ADD_FAILURE() << "no error for " << solids;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(CsgPrimitive, SceneReaderReadsAxesAndCapsulesAndNamesBadKeys) {
  const std::string path = writeSceneFile(
      R"({"cylinder": {"center": [0, 0, 0], "radius": 0.002, "halfHeight": 0.01, "axis": [0, 0, 2]}},
         {"capsule": {"from": [-0.01, 0, 0], "to": [0.01, 0, 0], "radius": 0.001}})");
  const HapticScene scene = loadHapticScene(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(scene.grid);
  // On the z axis 5 mm from the centre: inside the z cylinder (radius 2 mm, 10 mm half length); on the x axis 8 mm
  // out: inside the capsule only.
  EXPECT_LT(scene.grid->distance(Vec3(0, 0, 0.005)), -0.0015);
  EXPECT_NEAR(scene.grid->distance(Vec3(0.008, 0, 0)), -0.001, 1e-6);
  expectSceneError(R"({"cylinder": {"center": [0, 0, 0], "radius": 0.002, "halfHeight": 0.01, "axis": [0, 0, 0]}})",
                   "solids[0].cylinder.axis");
  expectSceneError(R"({"capsule": {"from": [0, 0, 0], "to": [0.01, 0, 0], "radius": -1}})", "solids[0].capsule.radius");
  expectSceneError(R"({"capsule": {"from": [0, 0, 0], "radius": 0.001}})", "solids[0].capsule.to");
  expectSceneError(R"({"capsule": {"from": [0, 0, 0], "to": [0.01, 0, 0], "radius": 0.001, "axis": [1, 0, 0]}})",
                   "axis");
  expectSceneError(R"({"box": {"center": [0, 0, 0], "halfExtents": [1, 1, 1]},
                       "capsule": {"from": [0, 0, 0], "to": [0.01, 0, 0], "radius": 0.001}})",
                   "solids[0]");
}

}  // namespace
}  // namespace sdfccd::haptics
