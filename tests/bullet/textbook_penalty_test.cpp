// Textbook mechanics in penalty mode (docs/design/contact-response.md, textbook suite): each test sets only geometry,
// masses and mu (scene `contact.friction`); shells, fields, stiffness and damping are the project's defaults
// (stiffness per area, damping ratio from restitution, Blend direction, anchor friction) at 1 ms steps.
// Tests whose name ends in `Short` form the subset the sanitizer builds run (gtest filter `*Short*`).
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bullet/compound_on_ground.h"
#include "bullet_test_util.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/bullet/contact_system.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "sdfccd/mesh/procedural_meshes.h"
#include "sdfccd/response/contact_material.h"

namespace sdfccd {
namespace textbook_penalty_test {

constexpr double kG = 9.81;     // m/s^2
constexpr double kHalf = 0.05;  // m, half size of the test boxes

/// One body of a test scene, as JSON.
std::string boxBody(const std::string& name, const Vec3& position, double mass = 1.0, double half = kHalf,
                    int resolution = 32) {
  std::ostringstream j;
  j.precision(10);
  j << R"({"name": ")" << name << R"(", "primitive": {"type": "box", "half_extents": [)" << half << ", " << half << ", "
    << half << "]}, \"mass\": " << mass << ", \"position\": [" << position.x() << ", " << position.y() << ", "
    << position.z() << "], \"resolution\": " << resolution << "}";
  return j.str();
}

std::string bunnyBody(const std::string& name, const Vec3& position) {
  std::ostringstream j;
  j.precision(10);
  j << R"({"name": ")" << name
    << R"(", "mesh": "meshes/bunny.off", "scale": 0.2, "points": 777, "resolution": 64, "mass": 1.0,)"
    << " \"position\": [" << position.x() << ", " << position.y() << ", " << position.z() << "]}";
  return j.str();
}

/// A scene with ground, gravity, damping, rotation and friction on, the project's contact defaults and mu.
Scene textbookScene(const std::vector<std::string>& bodies, double mu, const Vec3& gravity = Vec3(0, -kG, 0),
                    bool sleeping = false) {
  std::ostringstream j;
  j.precision(12);
  j << R"({"timestep": 0.001, "gravity": [)" << gravity.x() << ", " << gravity.y() << ", " << gravity.z()
    << R"(], "effects": ["gravity", "ground", "damping", "rotation", "friction"], "sleeping": )"
    << (sleeping ? "true" : "false") << R"(, "contact": {"mode": "penalty", "friction": )" << mu << R"(}, "bodies": [)";
  for (std::size_t i = 0; i < bodies.size(); ++i) j << (i ? ", " : "") << bodies[i];
  j << "]}";
  return test::sceneFromText(j.str());
}

bullet::SceneWorldSettings cached() {
  bullet::SceneWorldSettings s;
  s.cacheDir = "textbook-model-cache";
  return s;
}

/// Least-squares a of x(t) = x0 + v0 t + a t^2 / 2.
double fitAcceleration(const std::vector<double>& t, const std::vector<double>& x) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < t.size(); ++i) {
    const Eigen::Vector3d row(1.0, t[i], 0.5 * t[i] * t[i]);
    A += row * row.transpose();
    b += row * x[i];
  }
  return A.ldlt().solve(b)(2);
}

struct InclineResult {
  double acceleration = 0.0;  // m/s^2, fitted from 0.5 s to the end
  double travel = 0.0;        // m, along the slope from 0.5 s to the end
};

/// A 10 cm, 1 kg box on the ground under gravity tilted by theta (the incline), `seconds` (>= 1.5).
InclineResult runIncline(double thetaDegrees, double mu, double seconds) {
  const double theta = thetaDegrees * kPi / 180.0;
  const Vec3 gravity(kG * std::sin(theta), -kG * std::cos(theta), 0.0);
  bullet::SceneWorld world(textbookScene({boxBody("box", Vec3(0, kHalf + 0.0005, 0))}, mu, gravity), cached());
  std::vector<double> ts, xs;
  double x05 = 0.0;
  const int steps = static_cast<int>(std::lround(seconds / 0.001));
  for (int step = 1; step <= steps; ++step) {
    world.step();
    const double t = step * 0.001;
    const double x = world.bodyState(0).position.x();
    if (step == 500) x05 = x;
    if (step >= 500 && step % 10 == 0) {
      ts.push_back(t);
      xs.push_back(x);
    }
  }
  InclineResult r;
  r.acceleration = fitAcceleration(ts, xs);
  r.travel = world.bodyState(0).position.x() - x05;
  return r;
}

void expectIncline(double thetaDegrees, double mu) {
  const double theta = thetaDegrees * kPi / 180.0;
  const double expected = kG * (std::sin(theta) - mu * std::cos(theta));
  // Sticking is claimed between 0.5 and 2.5 s; a slide's acceleration is fitted over [0.5, 1.5] s (100 samples;
  // over [0.5, 2.5] s the slides match Coulomb within 0.01% too, so the longer window would only cost time).
  const double seconds = expected <= 0.0 ? 2.5 : 1.5;
  const InclineResult r = runIncline(thetaDegrees, mu, seconds);
  std::printf("incline theta %.1f deg mu %.2f: a = %.4f m/s^2 (Coulomb %.4f), travel 0.5-%.1f s = %.3g m\n",
              thetaDegrees, mu, r.acceleration, std::max(expected, 0.0), seconds, r.travel);
  if (expected <= 0.0) {
    EXPECT_LT(std::abs(r.travel), 1e-3) << "theta " << thetaDegrees << " mu " << mu;
  } else {
    EXPECT_NEAR(r.acceleration / expected, 1.0, 0.05) << "theta " << thetaDegrees << " mu " << mu;
  }
}

double atanDegrees(double mu) {
  return std::atan(mu) * 180.0 / kPi;
}

TEST(TextbookPenalty, InclineSticksBelowAtanMu) {
  expectIncline(atanDegrees(0.5) - 3.0, 0.5);
}

TEST(TextbookPenalty, InclineSlidesAboveAtanMuShort) {
  expectIncline(atanDegrees(0.5) + 5.0, 0.5);
}

TEST(TextbookPenalty, InclineSweep) {
  for (double mu : {0.3, 0.8}) {
    for (double offset : {-8.0, -3.0, 5.0, 15.0}) expectIncline(atanDegrees(mu) + offset, mu);
  }
  expectIncline(atanDegrees(0.5) - 8.0, 0.5);
  expectIncline(atanDegrees(0.5) + 15.0, 0.5);
}

// The pair's damping is Rayleigh damping of its elastic wrench (penalty_model.cpp, PairDamping): per-point dampers
// alone, pushing harder on the patch's approaching front than on its receding back, brake the roll to
// a = 0.69 of 5/7 g sin theta (1.66 m/s^2; with damping off 0.99); with the pair's Rayleigh damping it rolls at 0.98.
TEST(TextbookPenalty, SphereRollsAtFiveSeventhsGSinTheta) {
  const double theta = 20.0 * kPi / 180.0;
  const Vec3 gravity(kG * std::sin(theta), -kG * std::cos(theta), 0.0);
  const std::string sphere =
      R"({"name": "ball", "primitive": {"type": "sphere", "radius": 0.05, "subdivisions": 4}, "mass": 1.0,)"
      R"( "position": [0, 0.0505, 0], "resolution": 32})";
  bullet::SceneWorld world(textbookScene({sphere}, 0.5, gravity), cached());
  std::vector<double> ts, xs;
  for (int step = 1; step <= 2000; ++step) {
    world.step();
    if (step >= 300 && step % 10 == 0) {
      ts.push_back(step * 0.001);
      xs.push_back(world.bodyState(0).position.x());
    }
  }
  const double a = fitAcceleration(ts, xs);
  const double expected = 5.0 / 7.0 * kG * std::sin(theta);
  const bullet::SceneBodyState s = world.bodyState(0);
  const double rolling = -s.angularVelocity.z() * 0.05;  // omega r of rolling along +x
  std::printf("sphere: a = %.4f m/s^2 (5/7 g sin theta = %.4f), v = %.4f, omega r = %.4f\n", a, expected,
              s.linearVelocity.x(), rolling);
  EXPECT_NEAR(a / expected, 1.0, 0.05);
  EXPECT_NEAR(rolling / s.linearVelocity.x(), 1.0, 0.05);
}

bool allDynamicAsleep(bullet::SceneWorld& world) {
  for (int i = 0; i < world.bodyCount(); ++i) {
    if (!world.isStatic(i) && world.body(i).getActivationState() != ISLAND_SLEEPING) return false;
  }
  return true;
}

/// Runs up to `seconds`, then checks that no dynamic body's centre moved more than 1 mm between t = 1 s and the
/// end and that the largest penetration at rest (the last step with contacts) is under 1 cell. Once every
/// dynamic body sleeps (after 1 s), the run stops: Bullet moves no sleeping body, and nothing in these scenes
/// wakes one (no external agent, the islands are all asleep), so the positions at `seconds` are those of now.
void expectStands(bullet::SceneWorld& world, double seconds, const std::string& what) {
  const int steps = static_cast<int>(std::lround(seconds / 0.001));
  std::vector<Vec3> at1;
  double lastPenetration = 0.0;  // cells, at the last step that had contacts
  int step = 1;
  for (; step <= steps; ++step) {
    world.step();
    double penetration = 0.0;
    for (const bullet::PairContact& c : world.contacts().lastStepContacts()) {
      penetration = std::max(penetration, c.maxPenetrationCells);
    }
    if (world.lastFrame().contacts > 0) lastPenetration = penetration;
    if (step == 1000) {
      for (int i = 0; i < world.bodyCount(); ++i) at1.push_back(world.bodyState(i).position);
    }
    if (step >= 1000 && allDynamicAsleep(world)) break;
  }
  double drift = 0.0;
  for (int i = 0; i < world.bodyCount(); ++i) {
    if (world.isStatic(i)) continue;
    drift = std::max(drift, (world.bodyState(i).position - at1[static_cast<std::size_t>(i)]).norm());
  }
  const double stopped = std::min(step, steps) * 0.001;
  std::printf(
      "%s: largest drift 1 s -> %.0f s = %.3g mm (all asleep from %.2f s), penetration at rest %.3f cells, "
      "max ever %.3f\n",
      what.c_str(), seconds, drift * 1e3, stopped, lastPenetration, world.maxPenetrationCells());
  EXPECT_FALSE(world.hasNonFinite()) << what;
  EXPECT_LT(drift, 1e-3) << what;
  EXPECT_GT(lastPenetration, 0.0) << what << ": never in contact";
  EXPECT_LT(lastPenetration, 1.0) << what;
}

std::vector<std::string> stack(int count, double gap = 0.001) {
  std::vector<std::string> bodies;
  for (int i = 0; i < count; ++i) {
    bodies.push_back(boxBody("box" + std::to_string(i), Vec3(0, kHalf + i * (2 * kHalf + gap) + gap, 0)));
  }
  return bodies;
}

TEST(TextbookPenalty, StackOfThreeStands) {
  bullet::SceneWorld world(textbookScene(stack(3), 0.5, Vec3(0, -kG, 0), true), cached());
  expectStands(world, 10.0, "stack of 3");
}

TEST(TextbookPenalty, StackOfTenStands) {
  bullet::SceneWorld world(textbookScene(stack(10), 0.5, Vec3(0, -kG, 0), true), cached());
  expectStands(world, 10.0, "stack of 10");
}

TEST(TextbookPenalty, PyramidOfFifteenStands) {
  std::vector<std::string> bodies;
  int n = 0;
  for (int row = 0; row < 5; ++row) {
    const int count = 5 - row;
    for (int k = 0; k < count; ++k) {
      const double x = (k - 0.5 * (count - 1)) * (2 * kHalf + 0.01);
      bodies.push_back(boxBody("b" + std::to_string(n++), Vec3(x, kHalf + row * (2 * kHalf + 0.001) + 0.001, 0)));
    }
  }
  bullet::SceneWorld world(textbookScene(bodies, 0.5, Vec3(0, -kG, 0), true), cached());
  expectStands(world, 10.0, "pyramid of 15");
}

// The light box feels both its contacts at once (omega^2 = (K_ground + 2 K_top) / m): per-pair caps alone leave
// it at the explicit limit (2.08 cells deep at the end, 165 mm of drift). Contact mass scaling
// (ContactLoads::applyContactMass) keeps each body within the caps with its whole load, at full stiffness.
TEST(TextbookPenalty, HeavyOnLightStands) {
  bullet::SceneWorld world(textbookScene({boxBody("light", Vec3(0, kHalf + 0.001, 0), 0.1),
                                  boxBody("heavy", Vec3(0, 3 * kHalf + 0.002, 0), 10.0)},
                                 0.5, Vec3(0, -kG, 0), true),
                   cached());
  expectStands(world, 10.0, "10 kg on 0.1 kg");
}

TEST(TextbookPenalty, RestingBunnyComesToRestAndSleepsShort) {
  Scene scene = textbookScene({bunnyBody("bunny", Vec3(0, 0.2, 0))}, 0.5, Vec3(0, -kG, 0), true);
  bullet::SceneWorld world(scene, cached());
  for (int step = 1; step <= 10000; ++step) world.step();
  const double energy = world.kineticEnergy();
  std::printf("resting bunny at 10 s: kinetic energy %.3g J, activation state %d\n", energy,
              world.body(0).getActivationState());
  EXPECT_LT(energy, 1e-6);
  EXPECT_EQ(world.body(0).getActivationState(), ISLAND_SLEEPING);
}

TEST(TextbookPenalty, EnergyNeverExceedsItsPreContactMaximumShort) {
  // No gravity, no external work: a bunny at 2 m/s spinning at 3 rad/s hits a static box wall (e = 0.5).
  const std::string wall = R"({"name": "wall", "primitive": {"type": "box", "half_extents": [0.05, 0.3, 0.3]},)"
                           R"( "static": true, "position": [0.3, 0, 0], "resolution": 32})";
  std::string bunny = bunnyBody("bunny", Vec3(0, 0, 0));
  bunny.insert(bunny.size() - 1, R"(, "velocity": [2, 0, 0], "angular_velocity": [0, 0, 3])");
  std::ostringstream j;
  j << R"({"timestep": 0.001, "effects": ["damping", "rotation", "friction"], "contact": {"mode": "penalty", "friction": 0.5},)"
    << R"( "sleeping": false, "bodies": [)" << wall << ", " << bunny << "]}";
  bullet::SceneWorld world(test::sceneFromText(j.str()), cached());
  world.body(0).setRestitution(1.0);
  world.body(1).setRestitution(0.5);
  double before = world.kineticEnergy();
  double largest = 0.0;
  bool touched = false;
  for (int step = 1; step <= 1000; ++step) {
    world.step();
    touched = touched || world.lastFrame().contacts > 0;
    const double energy = world.kineticEnergy();
    if (!touched) before = std::max(before, energy);
    largest = std::max(largest, energy);
  }
  std::printf("energy bound: before contact %.4f J, largest %.4f J, at the end %.4f J\n", before, largest,
              world.kineticEnergy());
  EXPECT_TRUE(touched);
  EXPECT_LE(largest, before * (1.0 + 1e-3));
}

/// The closed-form rebound of a linear spring-dashpot without tension (it lets go when k x + c v reaches 0, not at
/// x = 0): with x(t) = A e^(-zeta w t) sin(w_d t), release at tan(w_d t) = -2 zeta sqrt(1 - zeta^2) / (1 - 2 zeta^2),
/// e = e^(-zeta w t) (zeta w / w_d sin(w_d t) - cos(w_d t)). Above e(zeta) = exp(-zeta pi / sqrt(1 - zeta^2)).
double noTensionRestitution(double zeta) {
  const double root = std::sqrt(1.0 - zeta * zeta);
  double phase = std::atan2(-2.0 * zeta * root, 1.0 - 2.0 * zeta * zeta);  // w_d t, in (pi/2, pi]
  if (phase <= 0.0) phase += kPi;
  return std::exp(-zeta * phase / root) * (zeta / root * std::sin(phase) - std::cos(phase));
}

/// The rebound of the penalty law in one dimension, as the contact system integrates it (same-step timing): a
/// mass m at approach speed vIn hits a linear spring-dashpot K, C (no tension: each damper stops at zero force)
/// and each step of dt takes the impulse of the midpoint rule (5 pieces) over the part of the predicted path
/// x(t) = x0 + v1 t (v1 = v + g dt) that is inside, the damper seeing the velocity interpolated from v to v1;
/// then v' = v1 - J / m, x' = x0 + v' dt. Returns v_out / v_in. With dt -> 0 it tends to noTensionRestitution
/// (checked below); at omega dt = 0.32 the same-step impulse, taken over the predicted path, also takes about
/// alpha / 2 = K dt^2 / 2m of the energy a step.
double sameStepRestitution(double mass, double stiffness, double damping, double vIn, double dt, double gravity = kG) {
  double x = -vIn * dt * 0.37;  // penetration (m, > 0 inside); starts outside, arbitrary phase
  double v = vIn;               // approach speed (m/s)
  bool inside = false;
  for (int step = 0; step < 100000; ++step) {
    const double v1 = v + gravity * dt;
    double impulse = 0.0;
    const double x1 = x + v1 * dt;
    // The part of [0, dt] where x(t) > 0.
    double a = 0.0, b = dt;
    if (x <= 0.0 && x1 <= 0.0) {
      b = a;
    } else if (x <= 0.0) {
      a = -x / v1;
    } else if (x1 <= 0.0) {
      b = -x / v1;
    }
    const double piece = (b - a) / 5.0;
    for (int j = 0; j < 5 && piece > 0.0; ++j) {
      const double t = a + (j + 0.5) * piece;
      const double speed = v + (v1 - v) * t / dt;
      impulse += piece * std::max(0.0, stiffness * (x + v1 * t) + damping * speed);
    }
    v = v1 - impulse / mass;
    x += v * dt;
    inside = inside || impulse > 0.0;
    if (inside && x < 0.0 && v < 0.0) return -v / vIn;
  }
  return 0.0;
}

TEST(TextbookPenalty, ReboundIsTheSameStepSpringDashpotsShort) {
  // Penalty mode: a 1 kg box dropped flat from h = 0.3 m with restitution e. The rebound comes from the damping
  // ratio zeta(e) of the pair (contact_material.h: zeta = -ln e / sqrt(pi^2 + ln^2 e), whose continuous spring-dashpot
  // gives back e, or a little more without tension) integrated at 1 ms by the same-step scheme: measured
  // e_eff = 0.25, 0.46, 0.68 for e = 0.3, 0.6, 0.9 (no time-of-impact clamp fires: 2.4 mm a step < 0.5 cell).
  // The answer to match is that law's rebound (sameStepRestitution), with K = k_A S = 1e7 N/m^3 * 0.01 m^2, and it
  // must stay below the continuous law's e (the same-step scheme only takes energy away).
  const double h = 0.3;
  const double mass = 1.0;
  const double stiffness = 1.0e7 * (2 * kHalf) * (2 * kHalf);  // N/m, the default k_A times the face
  const double vIn = std::sqrt(2.0 * kG * h);
  for (double e : {0.3, 0.6, 0.9}) {
    bullet::SceneWorld world(textbookScene({boxBody("box", Vec3(0, kHalf + h, 0))}, 0.5), cached());
    btCollisionObjectArray& objects = world.world().getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i) objects[i]->setRestitution(1.0);  // the ground: combined e = e_body
    world.body(0).setRestitution(btScalar(e));
    bool hit = false;
    double exitSpeed = 0.0;
    int clamps = 0;
    for (int step = 1; step <= 800 && exitSpeed == 0.0; ++step) {
      world.step();
      clamps += world.lastFrame().clamps;
      if (world.lastFrame().contacts > 0) hit = true;
      if (hit && world.lastFrame().contacts == 0) exitSpeed = world.bodyState(0).linearVelocity.y();
    }
    const double zeta = dampingRatioFromRestitution(e);
    const double damping = 2.0 * zeta * std::sqrt(stiffness * mass);
    const double expected = sameStepRestitution(mass, stiffness, damping, vIn, 0.001);
    const double measured = exitSpeed / vIn;
    // The reference law itself: at dt = 10 us and without gravity it is the continuous one without tension.
    EXPECT_NEAR(sameStepRestitution(mass, stiffness, damping, vIn, 1e-5, 0.0), noTensionRestitution(zeta), 0.005);
    std::printf(
        "rebound e = %.1f (zeta %.3f): e_eff = %.3f, same-step spring-dashpot %.3f, continuous %.3f (without "
        "tension %.3f), clamps %d\n",
        e, zeta, measured, expected, restitutionFromDampingRatio(zeta), noTensionRestitution(zeta), clamps);
    EXPECT_TRUE(hit) << "e " << e;
    EXPECT_EQ(clamps, 0) << "e " << e;
    EXPECT_LT(measured, restitutionFromDampingRatio(zeta)) << "e " << e;
    // 10%, the tolerance for a rebound (measured ratios 0.95, 0.96, 0.97: the box's edge points and its
    // friction are not in the one-dimensional law).
    EXPECT_NEAR(measured / expected, 1.0, 0.10) << "e " << e;
  }
}

TEST(TextbookPenalty, KinematicBoxPushesABunnyShort) {
  // A 20 cm kinematic box at 1 m/s along x pushes a resting bunny ahead of it for 0.5 s.
  std::string pusher =
      R"({"name": "pusher", "primitive": {"type": "box", "half_extents": [0.1, 0.1, 0.1]},)"
      R"( "kinematic": true, "velocity": [1, 0, 0], "position": [-0.215, 0.1005, 0], "resolution": 32})";
  bullet::SceneWorld world(textbookScene({bunnyBody("bunny", Vec3(0, 0.07, 0)), pusher}, 0.5), cached());
  for (int step = 1; step <= 200; ++step) world.step();  // the bunny settles first; the box is still away
  double deepest = 0.0, fastest = 0.0;
  double lastSpeed = 0.0;
  for (int step = 1; step <= 500; ++step) {
    world.step();
    deepest = std::max(deepest, world.lastFrame().penetrationCells);
    const bullet::SceneBodyState bunny = world.bodyState(0);
    fastest = std::max(fastest, bunny.linearVelocity.norm());
    lastSpeed = bunny.linearVelocity.x();
  }
  const double front = world.bodyState(1).position.x() + 0.1;
  std::printf(
      "kinematic pusher: deepest %.3f cells, bunny speed %.3f m/s (fastest %.3f), bunny x %.3f, box front %.3f\n",
      deepest, lastSpeed, fastest, world.bodyState(0).position.x(), front);
  EXPECT_LT(deepest, 1.0);
  EXPECT_NEAR(lastSpeed, 1.0, 0.1);
  EXPECT_LT(fastest, 1.5);
  EXPECT_GT(world.bodyState(0).position.x(), front);
}

TEST(TextbookPenalty, TwoChildCompoundRestsOnTheGround) {
  bullet::ContactSettings settings;
  settings.mode = SdfccdContactMode::Penalty;
  settings.penalty.frictionFromBodies = false;
  settings.penalty.friction = 0.5;
  btTransform left, right;
  left.setIdentity();
  left.setOrigin(btVector3(btScalar(-0.08), 0, 0));
  right.setIdentity();
  right.setOrigin(btVector3(btScalar(0.08), 0, 0));
  test::CompoundOnGround scene(settings, kHalf, left, right, kHalf + 0.05, kG);
  scene.body().setActivationState(DISABLE_DEACTIVATION);
  scene.step(3000, 0.001);
  const double cell = scene.cellSize();
  for (int child = 0; child < 2; ++child) EXPECT_GT(scene.lowestShellPoint(child), -cell);
  const double height = scene.body().getWorldTransform().getOrigin().y();
  const btVector3 omega = scene.body().getAngularVelocity();
  std::printf("compound: centre height %.4f m (half height %.3f), omega (%.3g, %.3g, %.3g) rad/s\n", height, kHalf,
              double(omega.x()), double(omega.y()), double(omega.z()));
  EXPECT_NEAR(height, kHalf, cell);
  EXPECT_LT(omega.length(), 0.01);
}

}  // namespace textbook_penalty_test
}  // namespace sdfccd
