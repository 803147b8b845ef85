/// @file
/// @brief GodObject with Coulomb friction (GodObjectSettings::qp.friction) on the ground plane, in virtual time
/// (one cycle = 1 ms): a cube pushed sideways below the static bound never creeps in 10 s; pushed above it, it
/// slides with the rendered tangential force mu times the normal force along a pyramid edge and mu cos(pi/p)
/// across a face; friction 0 renders no tangential force.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "haptics/haptic_test_scenes.h"
#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/haptics/god_object.h"
#include "sdfccd/haptics/haptic_scene.h"
#include "sdfccd/shell/point_shell.h"

namespace sdfccd::haptics {
namespace god_object_friction_test {

constexpr double kHalf = 0.01;   // the cube's half extent (m)
constexpr double kPress = 5e-3;  // the device is held this far below the resting god-object: normal force k * kPress

Rigid at(const Vec3& p) {
  Rigid r = Rigid::Identity();
  r.translation() = p;
  return r;
}

// The cube's eight corners: four touch the ground, so the contact set is the four bottom corners.
PointTree cornerTree() {
  PointShell shell;
  for (int i = 0; i < 8; ++i) {
    const Vec3 c((i & 1) ? kHalf : -kHalf, (i & 2) ? kHalf : -kHalf, (i & 4) ? kHalf : -kHalf);
    shell.positions.push_back(c);
    shell.normals.push_back(c.normalized());
  }
  return PointTree(shell);
}

GodObjectSettings frictionSettings(double mu) {
  GodObjectSettings s;
  s.sigma = 2e-5;
  s.contactThreshold = 5e-5;
  s.maxStepTranslation = 2e-3;
  s.qp.friction = mu;
  s.qp.frictionFaces = 8;
  return s;
}

// Rests the god-object on the ground with the device straight below it (pressing with k * kPress).
void settle(GodObject& god) {
  for (int cycle = 0; cycle < 50; ++cycle) {
    const GodObjectStepResult r = god.step(at(Vec3(0, kHalf - kPress, 0)));
    ASSERT_NE(r.qpState, ContactQpState::Failed);
  }
  ASSERT_EQ(god.contacts().size(), 4u);
}

TEST(GodObjectFriction, BelowTheStaticBoundTheToolNeverCreepsIn10Seconds) {
  const PointTree tree = cornerTree();
  const PlaneField ground = PlaneField::ground();
  const double mu = 0.5;
  GodObject god(ObstacleContacts(tree, ground, Rigid::Identity()), at(Vec3(0, kHalf + 2e-5, 0)), frictionSettings(mu));
  settle(god);
  const Rigid rest = god.pose();
  // Tangential offset 0.8 mu cos(pi/8) kPress at 30 degrees from x: below the bound in every direction.
  const double offset = 0.8 * mu * std::cos(kPi / 8.0) * kPress;
  const Vec3 direction(std::cos(kPi / 6.0), 0.0, std::sin(kPi / 6.0));
  const double k = god.settings().renderStiffness;
  GodObjectStepResult last;
  for (int cycle = 0; cycle < 10000; ++cycle) {  // 10 s: a 0.1 s ramp, then held
    const double s = std::min(1.0, cycle / 100.0);
    last = god.step(at(rest.translation() + Vec3(0, -kPress, 0) + s * offset * direction));
    ASSERT_NE(last.qpState, ContactQpState::Failed) << cycle;
    ASSERT_EQ(last.contactCount, 4) << cycle;
  }
  const Vec3 drift = god.pose().translation() - rest.translation();
  EXPECT_EQ(drift.x(), 0.0);  // no creep at all: a sticking solve is exactly zero motion
  EXPECT_EQ(drift.z(), 0.0);
  EXPECT_LE(std::abs(drift.y()), 1e-9);
  EXPECT_TRUE(god.pose().linear().isApprox(rest.linear(), 1e-15));
  // The rendered force is the spring's: k kPress up, k offset back against the push.
  EXPECT_NEAR(last.wrenchOnDevice[1], k * (kPress + drift.y()), 1e-9);
  EXPECT_NEAR((last.wrenchOnDevice.head<3>().cwiseProduct(Vec3(1, 0, 1)) + k * offset * direction).norm(), 0.0, 1e-9);
}

// Drags the device along `direction` (horizontal) for 1 s at 1 cm/s; returns the last cycle's wrench.
Vec6 drag(double mu, const Vec3& direction, double& travelled) {
  const PointTree tree = cornerTree();
  const PlaneField ground = PlaneField::ground();
  GodObject god(ObstacleContacts(tree, ground, Rigid::Identity()), at(Vec3(0, kHalf + 2e-5, 0)), frictionSettings(mu));
  settle(god);
  const Rigid rest = god.pose();
  GodObjectStepResult r;
  for (int cycle = 0; cycle < 1000; ++cycle) {
    r = god.step(at(rest.translation() + Vec3(0, -kPress, 0) + 1e-5 * cycle * direction));
    EXPECT_NE(r.qpState, ContactQpState::Failed);
  }
  travelled = (god.pose().translation() - rest.translation()).dot(direction);
  return r.wrenchOnDevice;
}

TEST(GodObjectFriction, AboveTheBoundItSlidesWithMuTimesTheNormalForce) {
  const double mu = 0.5;
  const double inscribed = std::cos(kPi / 8.0);
  // Along x, an edge of the pyramid: tangential force exactly mu N, opposite the motion.
  double travelled = 0.0;
  const Vec6 alongEdge = drag(mu, Vec3::UnitX(), travelled);
  EXPECT_GT(travelled, 5e-3);  // it slides (the device went 1 cm; the spring holds mu kPress = 2.5 mm)
  EXPECT_NEAR(-alongEdge[0] / alongEdge[1], mu, 1e-9);
  EXPECT_NEAR(alongEdge[2], 0.0, 1e-9);
  EXPECT_NEAR(travelled, 1e-2 - 1e-5 - mu * kPress, 1e-4);
  // Across a face's middle (pi/8 from x): mu cos(pi/8) N, the pyramid's worst case.
  const Vec3 across(std::cos(kPi / 8.0), 0.0, std::sin(kPi / 8.0));
  const Vec6 acrossFace = drag(mu, across, travelled);
  const Vec3 tangential(acrossFace[0], 0.0, acrossFace[2]);
  EXPECT_GT(travelled, 5e-3);
  EXPECT_NEAR(tangential.norm() / acrossFace[1], mu * inscribed, 1e-9);
  EXPECT_NEAR(tangential.normalized().dot(across), -1.0, 1e-9);
  // Frictionless: no tangential force at all, the god-object follows the device.
  const Vec6 frictionless = drag(0.0, Vec3::UnitX(), travelled);
  EXPECT_NEAR(frictionless[0], 0.0, 1e-9);
  EXPECT_NEAR(travelled, 1e-2 - 2e-5, 1e-9);  // the device at 0.00999 less the coupling lag v (1 - k_s) / k_s
}

TEST(GodObjectFriction, BadFrictionSettingsAreRejected) {
  const PointTree tree = cornerTree();
  const PlaneField ground = PlaneField::ground();
  GodObjectSettings s = frictionSettings(-0.1);
  EXPECT_THROW(GodObject(ObstacleContacts(tree, ground, Rigid::Identity()), at(Vec3(0, 0.05, 0)), s), Error);
  s = frictionSettings(0.5);
  s.qp.frictionFaces = 2;
  EXPECT_THROW(GodObject(ObstacleContacts(tree, ground, Rigid::Identity()), at(Vec3(0, 0.05, 0)), s), Error);
}

// The plane-slide scene with `constraintExtra` added to its "constraint" object, written to a temporary file.
std::string sceneWith(const std::string& constraintExtra, const std::string& fileName) {
  std::ifstream in(test::scenePath("plane-slide.json"));
  std::stringstream text;
  text << in.rdbuf();
  std::string json = text.str();
  const std::size_t at = json.find("\"constraint\": {");
  EXPECT_NE(at, std::string::npos);
  json.insert(at + std::string("\"constraint\": {").size(), constraintExtra);
  const std::string path = ::testing::TempDir() + "/" + fileName;
  std::ofstream(path) << json;
  return path;
}

TEST(GodObjectFriction, SceneKeysAreReadAndABadValueNamesTheKey) {
  EXPECT_EQ(loadHapticScene(test::scenePath("plane-slide.json")).god.qp.friction, 0.0);  // default: frictionless
  const HapticScene scene = loadHapticScene(sceneWith("\"friction\": 0.4, \"frictionFaces\": 12, ", "fric_ok.json"));
  EXPECT_EQ(scene.god.qp.friction, 0.4);
  EXPECT_EQ(scene.god.qp.frictionFaces, 12);
  for (const std::string& bad : {std::string("\"friction\": -0.5, "), std::string("\"frictionFaces\": 2, ")}) {
    try {
      loadHapticScene(sceneWith(bad, "fric_bad.json"));
      ADD_FAILURE() << bad;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(
          message.find(bad.find("Faces") != std::string::npos ? "constraint.frictionFaces" : "constraint.friction"),
          std::string::npos)
          << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
}

}  // namespace god_object_friction_test
}  // namespace sdfccd::haptics
