// Bodies on bodies: the textbook cases on supports that have shells of their own (a static box table, a kinematic
// belt) as well as on the analytic ground, at several start offsets against the support's point grid, at the
// defaults (only geometry, masses, materials, start velocities and the step set; sleeping off, so that rest is
// judged by the mechanics). Each case has its analytic answer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bullet_test_util.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/error.h"

namespace sdfccd::bodies_textbook {
using bullet::SceneBodyState;
using bullet::SceneWorld;
using bullet::SceneWorldSettings;
namespace {

constexpr double kG = 9.81;
constexpr double kSolverStep = 1.0 / 240.0;
constexpr double kHalf = 0.05;            // the moving box: 10 cm
constexpr double kTableTop = 0.1;         // the table: 2 m x 0.2 m x 1 m, top face at y = 0.1
constexpr double kTableSpacing = 0.0125;  // its shell's point spacing: 1/16 of its 0.2 m side

std::string vec(double x, double y, double z) {
  std::ostringstream s;
  s.precision(17);
  s << "[" << x << ", " << y << ", " << z << "]";
  return s.str();
}

/// A body of the scene, as JSON.
struct Body {
  std::string name = "box";
  std::string primitive = "{\"type\": \"box\", \"half_extents\": [0.05, 0.05, 0.05]}";
  std::string kind = "\"mass\": 1.0";  // or "\"static\": true", "\"kinematic\": true"
  double friction = 0.5;
  double restitution = 0.0;
  std::string position = vec(0, 0, 0);
  std::string velocity = vec(0, 0, 0);

  std::string json() const {
    return "{\"name\": \"" + name + "\", \"primitive\": " + primitive + ", " + kind +
           ", \"friction\": " + std::to_string(friction) + ", \"restitution\": " + std::to_string(restitution) +
           ", \"position\": " + position + ", \"velocity\": " + velocity + "}";
  }
};

Body table() {
  Body b;
  b.name = "table";
  b.primitive = "{\"type\": \"box\", \"half_extents\": [1.0, 0.1, 0.5]}";
  b.kind = "\"static\": true";
  b.friction = 1.0;
  b.restitution = 1.0;
  return b;
}

Body sphere(double radius) {
  Body b;
  b.name = "ball";
  std::ostringstream s;
  s << "{\"type\": \"sphere\", \"radius\": " << radius << "}";
  b.primitive = s.str();
  return b;
}

struct SceneSpec {
  std::string mode = "solver";
  double step = kSolverStep;
  std::vector<std::string> effects = {"gravity", "rotation", "friction"};
  std::string gravity = vec(0, -kG, 0);
  std::string contactExtra;  // more keys of "contact"
  std::string groundExtra;   // keys of "ground"
  std::vector<Body> bodies;

  std::string text() const {
    std::ostringstream s;
    s.precision(17);
    s << "{\"timestep\": " << step << ", \"gravity\": " << gravity << ", \"effects\": [";
    for (std::size_t i = 0; i < effects.size(); ++i) s << (i ? ", " : "") << "\"" << effects[i] << "\"";
    s << "], \"sleeping\": false, \"contact\": {\"mode\": \"" << mode << "\"" << contactExtra << "}";
    if (!groundExtra.empty()) s << ", \"ground\": {" << groundExtra << "}";
    s << ", \"bodies\": [";
    for (std::size_t i = 0; i < bodies.size(); ++i) s << (i ? ", " : "") << bodies[i].json();
    s << "]}";
    return s.str();
  }
};

/// Puts the support under the scene's bodies: "table" (a static box) or "ground" (the analytic plane). Returns the
/// height of its top face.
double addSupport(SceneSpec& spec, const std::string& support) {
  if (support == "table") {
    spec.bodies.push_back(table());
    return kTableTop;
  }
  spec.effects.push_back("ground");
  return 0.0;
}

std::unique_ptr<SceneWorld> makeWorld(const SceneSpec& spec) {
  SceneWorldSettings settings;
  settings.cacheDir = "textbook-model-cache";
  return std::make_unique<SceneWorld>(test::sceneFromText(spec.text()), settings);
}

/// The moving body's history: the largest upward speed and spin seen after `settle` seconds.
struct Motion {
  std::vector<double> time, x, y, vx, vy;
  double maxUpSpeed = 0.0;
  double maxSpin = 0.0;
};

Motion run(SceneWorld& world, int body, double seconds, double settle = 0.0) {
  Motion m;
  while (world.time() < seconds - 1e-9) {
    world.step();
    const SceneBodyState s = world.bodyState(body);
    m.time.push_back(world.time());
    m.x.push_back(s.position.x());
    m.y.push_back(s.position.y());
    m.vx.push_back(s.linearVelocity.x());
    m.vy.push_back(s.linearVelocity.y());
    if (world.time() > settle) {
      m.maxUpSpeed = std::max(m.maxUpSpeed, s.linearVelocity.y());
      m.maxSpin = std::max(m.maxSpin, s.angularVelocity.norm());
    }
    EXPECT_FALSE(world.hasNonFinite());
  }
  return m;
}

// --- Sliding: a box launched at 2 m/s with mu 0.5 stops after v0^2 / (2 mu g) --------------------------------

struct SlideCase {
  std::string support;  // "table" or "ground"
  double offset;        // start offset along the slide, in the table's point spacings
};

class SolverSlide : public ::testing::TestWithParam<SlideCase> {};

TEST_P(SolverSlide, BoxStopsAtTheCoulombDistanceWithoutBeingTripped) {
  const SlideCase c = GetParam();
  constexpr double v0 = 2.0, mu = 0.5;
  SceneSpec spec;
  const double base = addSupport(spec, c.support);
  Body box;
  box.friction = mu;  // the table's and the ground's 1: the pair's mu is the box's
  const double x0 = -0.6 + c.offset * kTableSpacing;
  box.position = vec(x0, base + kHalf + 2e-4, 0);  // landing from 0.2 mm
  box.velocity = vec(v0, 0, 0);
  spec.bodies.push_back(box);
  auto world = makeWorld(spec);
  const int index = world->bodyCount() - 1;
  const Motion m = run(*world, index, 0.6, 0.05);
  const double expected = v0 * v0 / (2 * mu * kG);  // 0.408 m
  const double travel = m.x.back() - x0;
  EXPECT_NEAR(travel, expected, 0.015 * expected) << c.support << " offset " << c.offset;
  EXPECT_LT(std::abs(m.vx.back()), 1e-3);
  EXPECT_LT(m.maxUpSpeed, 0.02) << "thrown up";
  EXPECT_LT(m.maxSpin, 0.2) << "tripped";
}

INSTANTIATE_TEST_SUITE_P(Offsets, SolverSlide,
                         ::testing::Values(SlideCase{"ground", 0.0}, SlideCase{"table", 0.0}, SlideCase{"table", 0.25},
                                           SlideCase{"table", 0.5}, SlideCase{"table", 0.75}),
                         [](const ::testing::TestParamInfo<SlideCase>& p) {
                           return p.param.support + "Quarter" + std::to_string(int(p.param.offset * 4));
                         });

// --- A kinematic belt at 1 m/s carries a dropped box up to its speed at mu g ----------------------------------

TEST(SolverBodies, BeltAcceleratesABoxAtMuGToItsSpeed) {
  constexpr double mu = 0.5, beltSpeed = 1.0;
  for (const double offset : {0.0, 0.5}) {
    SceneSpec spec;
    Body belt = table();
    belt.name = "belt";
    belt.primitive = "{\"type\": \"box\", \"half_extents\": [3.0, 0.05, 0.5]}";
    belt.kind = "\"kinematic\": true";
    belt.velocity = vec(beltSpeed, 0, 0);
    spec.bodies.push_back(belt);
    Body box;
    box.friction = mu;
    box.position = vec(offset * kTableSpacing, 0.05 + kHalf + 2e-3, 0);
    spec.bodies.push_back(box);
    auto world = makeWorld(spec);
    const Motion m = run(*world, 1, 0.6, 0.05);
    // The slope of vx while it slides (between 0.2 and 0.8 of the belt's speed).
    std::size_t a = 0, b = 0;
    for (std::size_t i = 0; i < m.vx.size(); ++i) {
      if (a == 0 && m.vx[i] > 0.2 * beltSpeed) a = i;
      if (b == 0 && m.vx[i] > 0.8 * beltSpeed) b = i;
    }
    ASSERT_GT(b, a);
    const double acceleration = (m.vx[b] - m.vx[a]) / (m.time[b] - m.time[a]);
    EXPECT_NEAR(acceleration, mu * kG, 0.03 * mu * kG) << "offset " << offset;
    EXPECT_NEAR(m.vx.back(), beltSpeed, 0.01 * beltSpeed);
    EXPECT_LT(m.maxUpSpeed, 0.02) << "thrown up";
    EXPECT_LT(m.maxSpin, 0.2) << "tripped";
  }
}

// --- Restitution: a drop from h rebounds to e^2 h; e = 1 neither loses nor gains ----------------------------------

/// The apexes of the body's centre above its resting height `rest`, over `h`.
std::vector<double> apexRatios(const Motion& m, double rest, double h) {
  std::vector<double> out;
  for (std::size_t i = 1; i + 1 < m.y.size(); ++i) {
    if (m.vy[i - 1] > 0.0 && m.vy[i] <= 0.0 && m.y[i] > rest + 1e-3) out.push_back((m.y[i] - rest) / h);
  }
  return out;
}

struct BounceCase {
  std::string body;     // "box" or "ball"
  std::string support;  // "ground" or "table"
};

class SolverBounce : public ::testing::TestWithParam<BounceCase> {};

SceneSpec bounceScene(const BounceCase& c, double e, double h, double& rest) {
  SceneSpec spec;
  const double base = addSupport(spec, c.support);
  Body b = c.body == "box" ? Body{} : sphere(kHalf);
  b.restitution = e;
  rest = base + kHalf;
  b.position = vec(0, rest + h, 0);
  spec.bodies.push_back(b);
  return spec;
}

TEST_P(SolverBounce, RestitutionOneKeepsTheDropHeightAndNeverGains) {
  constexpr double h = 0.3;
  double rest = 0.0;
  auto world = makeWorld(bounceScene(GetParam(), 1.0, h, rest));
  const Motion m = run(*world, world->bodyCount() - 1, 3.0);
  const std::vector<double> apex = apexRatios(m, rest, h);
  ASSERT_GE(apex.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_GT(apex[i], 0.95) << "bounce " << i + 1;
    EXPECT_LE(apex[i], 1.0 + 1e-3) << "bounce " << i + 1 << " rose above the drop height";
  }
}

TEST_P(SolverBounce, ReboundReachesESquaredH) {
  constexpr double h = 0.3;
  for (const double e : {0.3, 0.6, 0.9}) {
    double rest = 0.0;
    auto world = makeWorld(bounceScene(GetParam(), e, h, rest));
    const Motion m = run(*world, world->bodyCount() - 1, 0.8);
    const std::vector<double> apex = apexRatios(m, rest, h);
    ASSERT_FALSE(apex.empty()) << "e " << e;
    EXPECT_NEAR(apex[0], e * e, 0.1 * e * e) << "e " << e;
  }
}

INSTANTIATE_TEST_SUITE_P(Supports, SolverBounce,
                         ::testing::Values(BounceCase{"box", "ground"}, BounceCase{"ball", "ground"},
                                           BounceCase{"box", "table"}, BounceCase{"ball", "table"}),
                         [](const ::testing::TestParamInfo<BounceCase>& p) {
                           return p.param.body + "On" + p.param.support;
                         });

// Penalty mode: a ball hitting the ground faster than half a cell per step is stopped by the time-of-impact clamp,
// whose impact rebounds with the pair's restitution.
TEST(PenaltyBodies, ClampedBallReboundsToESquaredH) {
  constexpr double h = 0.3;
  for (const double e : {0.3, 0.6, 0.9}) {
    double rest = 0.0;
    SceneSpec spec = bounceScene(BounceCase{"ball", "ground"}, e, h, rest);
    spec.mode = "penalty";
    spec.step = 0.001;
    auto world = makeWorld(spec);
    const Motion m = run(*world, world->bodyCount() - 1, 0.8);
    const std::vector<double> apex = apexRatios(m, rest, h);
    ASSERT_FALSE(apex.empty()) << "e " << e << ": no rebound";
    EXPECT_NEAR(apex[0], e * e, 0.1 * e * e) << "e " << e;
  }
}

// --- Twisting: a cube spinning on its face slows at 6 (0.3826) mu g / a (Coulomb over a uniformly pressed square) ---

TEST(SolverBodies, SpinningCubeSlowsAtCoulombsTwistingFriction) {
  constexpr double mu = 0.5, side = 2 * kHalf, spin = 20.0;
  // The mean distance of a square's points from its centre, (sqrt 2 + asinh 1) / 6 of its side.
  const double meanRadius = (std::sqrt(2.0) + std::asinh(1.0)) / 6.0 * side;
  const double expected = mu * kG * meanRadius / (side * side / 6.0);  // torque / inertia: 112.6 rad/s^2
  for (const std::string support : {"ground", "table"}) {
    SceneSpec spec;
    const double base = addSupport(spec, support);
    Body box;
    box.friction = mu;
    box.position = vec(0, base + kHalf + 1e-4, 0);
    spec.bodies.push_back(box);
    // The spin: the scene's angular velocity key, added to the body's JSON.
    std::string text = spec.text();
    const std::string velocityKey = "\"velocity\": " + vec(0, 0, 0) + "}]";
    const auto at = text.rfind(velocityKey);
    ASSERT_NE(at, std::string::npos);
    text.replace(at, velocityKey.size(),
                 velocityKey.substr(0, velocityKey.size() - 2) + ", \"angular_velocity\": " + vec(0, spin, 0) + "}]");
    SceneWorldSettings settings;
    settings.cacheDir = "textbook-model-cache";
    SceneWorld world(test::sceneFromText(text), settings);
    const int index = world.bodyCount() - 1;
    std::vector<double> times, spins;
    while (world.time() < 0.12 - 1e-9) {
      world.step();
      times.push_back(world.time());
      spins.push_back(world.bodyState(index).angularVelocity.y());
    }
    // Between 0.02 s (landed) and 0.12 s (still spinning at about 9 rad/s).
    const std::size_t a = 4;
    const double deceleration = (spins[a] - spins.back()) / (times.back() - times[a]);
    EXPECT_NEAR(deceleration, expected, 0.1 * expected) << support;
  }
}

// --- The default sphere rolls: launched rolling at 1 m/s it keeps its speed but for a rolling resistance < 0.004 ---

TEST(SolverBodies, DefaultSphereRollsInBothModesOnTheGroundAndOnABox) {
  constexpr double radius = 0.05, speed = 1.0;
  for (const std::string mode : {"solver", "penalty"}) {
    for (const std::string support : {"ground", "table"}) {
      SceneSpec spec;
      spec.mode = mode;
      spec.step = mode == "solver" ? kSolverStep : 0.001;  // penalty mode's millisecond step
      const double base = addSupport(spec, support);
      Body ball = sphere(radius);  // the primitive's default subdivisions
      ball.position = vec(-0.5, base + radius + 1e-4, 0);
      ball.velocity = vec(speed, 0, 0);
      spec.bodies.push_back(ball);
      std::string text = spec.text();
      const std::string velocityKey = "\"velocity\": " + vec(speed, 0, 0) + "}]";
      const auto at = text.rfind(velocityKey);
      ASSERT_NE(at, std::string::npos);
      text.replace(at, velocityKey.size(),
                   velocityKey.substr(0, velocityKey.size() - 2) +
                       ", \"angular_velocity\": " + vec(0, 0, -speed / radius) + "}]");
      SceneWorldSettings settings;
      settings.cacheDir = "textbook-model-cache";
      SceneWorld world(test::sceneFromText(text), settings);
      const Motion m = run(world, world.bodyCount() - 1, 1.0);
      // A rolling sphere slows at (5/7) c g for a rolling resistance coefficient c.
      const double coefficient = (m.vx.front() - m.vx.back()) / (m.time.back() - m.time.front()) * 7.0 / 5.0 / kG;
      EXPECT_LT(coefficient, 0.004) << mode << " on the " << support;
      EXPECT_GT(coefficient, -0.001) << mode << " on the " << support << ": it gained speed";
      // Solver mode's rigid contact keeps the ball on the surface (penalty mode's point springs let a ball, whose
      // few contact points make a soft contact, sink and bob by millimetres: not a rolling resistance).
      if (mode == "solver") {
        EXPECT_LT(m.maxUpSpeed, 0.05) << "on the " << support << ": it hopped";
      }
    }
  }
}

// --- The scene's friction keys and effects hold in solver mode ------------------------------------------------

/// A box on the table tilted by `degrees` (gravity turned instead): its acceleration down the slope over 0.5 s.
double slopeAcceleration(SceneSpec spec, double degrees) {
  const double t = degrees * kPi / 180.0;
  spec.gravity = vec(kG * std::sin(t), -kG * std::cos(t), 0);
  spec.bodies.insert(spec.bodies.begin(), table());
  Body box;
  box.position = vec(-0.5, kTableTop + kHalf + 1e-4, 0);
  spec.bodies.push_back(box);
  auto world = makeWorld(spec);
  const Motion m = run(*world, 1, 0.5);
  const std::size_t a = m.vx.size() / 4;
  return (m.vx.back() - m.vx[a]) / (m.time.back() - m.time[a]);
}

TEST(SolverBodies, WithoutTheFrictionEffectABoxSlidesFrictionless) {
  SceneSpec spec;
  spec.effects = {"gravity", "rotation"};
  EXPECT_NEAR(slopeAcceleration(spec, 40.0), kG * std::sin(40.0 * kPi / 180.0), 0.02 * kG);
}

TEST(SolverBodies, ContactFrictionOverridesTheBodies) {
  SceneSpec spec;
  spec.contactExtra = ", \"friction\": 0.2";  // the bodies' would combine to 0.5
  const double t = 30.0 * kPi / 180.0;
  EXPECT_NEAR(slopeAcceleration(spec, 30.0), kG * (std::sin(t) - 0.2 * std::cos(t)), 0.02 * kG);
}

TEST(SolverBodies, TheGroundGivesABodyItsOwnFrictionUnlessItsMaterialIsSet) {
  for (const double groundFriction : {-1.0, 0.5}) {  // -1: the default ground
    SceneSpec spec;
    spec.effects.push_back("ground");
    if (groundFriction >= 0.0) spec.groundExtra = "\"friction\": " + std::to_string(groundFriction);
    Body box;
    box.friction = 0.5;
    box.position = vec(0, kHalf + 1e-4, 0);
    box.velocity = vec(2.0, 0, 0);
    spec.bodies.push_back(box);
    auto world = makeWorld(spec);
    const Motion m = run(*world, 0, 1.0);
    const double mu = 0.5 * (groundFriction >= 0.0 ? groundFriction : 1.0);
    const double expected = 4.0 / (2 * mu * kG);
    EXPECT_NEAR(m.x.back(), expected, 0.015 * expected) << "ground friction " << groundFriction;
  }
}

TEST(SolverBodies, GroundMaterialKeysAreCheckedByNameShort) {
  for (const std::string bad : {"\"friction\": -1", "\"restitution\": 1.5", "\"bounce\": 1"}) {
    SceneSpec spec;
    spec.effects.push_back("ground");
    spec.groundExtra = bad;
    spec.bodies.push_back(Body{});
    try {
      test::sceneFromText(spec.text());
      ADD_FAILURE() << "accepted ground {" << bad << "}";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("ground"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace sdfccd::bodies_textbook
