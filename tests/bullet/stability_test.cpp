// Stability: hard cases through the real plugin (SceneWorld), each checked against an analytic answer or a conservation
// law — a long resting contact (no energy gain, no drift, the analytic rest height), a stack, mass ratios of 1:1000,
// impacts at up to 100 cells per step, bodies starting interpenetrated, and NaN/inf state that must be rejected with a
// one-line error naming the body and field.
//
// Resting boxes use the mesh's 8 vertices as their shell (scene "points": 0): the 4 bottom corners carry the
// weight, so every rest depth is closed-form, d = (weight carried) / (4 k), and a step costs a few
// microseconds. The scenes use the conservative force direction ("direction": "field_gradient", see
// penalty_model.h); ShellNormalForceDirectionDriftsWhereFieldGradientRests shows why.
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "bullet_test_util.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/error.h"

namespace sdfccd {
namespace stability_test {

constexpr double kGravity = 9.81;  // m/s^2, the scenes' gravity (0, -g, 0)

// Total mechanical energy of the dynamic bodies without the contact springs: kinetic + m g y (J).
double mechanicalEnergy(const bullet::SceneWorld& world) {
  double energy = world.kineticEnergy();
  for (int i = 0; i < world.bodyCount(); ++i) {
    if (world.isStatic(i)) continue;
    energy += world.scene().bodies[static_cast<std::size_t>(i)].mass * kGravity * world.bodyState(i).position.y();
  }
  return energy;
}

// Rotation about the world's y axis (rad): the angle of the body's x axis in the ground plane.
double yawOf(const Quat& q) {
  const Vec3 x = q * Vec3::UnitX();
  return std::atan2(-x.z(), x.x());
}

// Rest depth of n shell points of stiffness k and damping c carrying a weight W on the static ground, in the
// plugin's default same-step timing: the impulse is integrated over the step's predicted motion, which
// starts at rest and ends g dt^2 deeper with approach speed g dt, so W dt = n (k (d + g dt^2 / 2) + c g dt / 2) dt.
double groundRestDepth(double weight, int n, double k, double c, double dt) {
  return weight / (n * k) - kGravity * dt * dt / 2 - c * kGravity * dt / (2 * k);
}

std::string boxBody(const std::string& name, double hx, double hy, double hz, double mass, double y,
                    const std::string& extra = "") {
  return "{ \"name\": \"" + name + "\", \"primitive\": { \"type\": \"box\", \"half_extents\": [" + std::to_string(hx) +
         ", " + std::to_string(hy) + ", " + std::to_string(hz) + "] }, \"mass\": " + std::to_string(mass) +
         ", \"position\": [0, " + std::to_string(y) + ", 0], \"points\": 0, \"resolution\": 16" + extra + " }";
}

// The penalty energy stored at the current poses: sum of k d^2 / 2 over the shell points of every body that
// are inside another body's field (both roles), d the depth (J). With the field-gradient direction the
// spring forces are minus the gradient of this energy.
double storedPenaltyEnergy(const bullet::SceneWorld& world, double k) {
  double energy = 0.0;
  for (int a = 0; a < world.bodyCount(); ++a) {
    for (int b = 0; b < world.bodyCount(); ++b) {
      if (a == b) continue;
      const bullet::SceneBodyState sa = world.bodyState(a), sb = world.bodyState(b);
      Rigid worldFromA = Rigid::Identity(), worldFromB = Rigid::Identity();
      worldFromA.linear() = sa.orientation.toRotationMatrix();
      worldFromA.translation() = sa.position;
      worldFromB.linear() = sb.orientation.toRotationMatrix();
      worldFromB.translation() = sb.position;
      const Rigid sdfFromShell = (worldFromB * world.model(b).bodyFromField()).inverse() * worldFromA;
      for (const Vec3& pointInShell : world.model(a).shell().positions) {
        const double depth = -world.model(b).field().distance(sdfFromShell * pointInShell);
        if (depth > 0) energy += 0.5 * k * depth * depth;
      }
    }
  }
  return energy;
}

// Steps of the long resting run: 10^5 (100 s at 1 ms) everywhere: short in Release, and within the time a sanitizer
// test may take under AddressSanitizer + UBSan.
constexpr int kRestingSteps = 100000;

// A box rests on the analytic ground for 10^5 steps of 1 ms (the conservative force direction, see
// penalty_model.h). After settling, kinetic + potential energy never rises above its value at the end of
// settling by more than 1e-6 J (Bullet's float state: m g times a few ulps of the height), the centre of
// mass stays within 1e-6 m of the axis horizontally, the yaw within 1e-6 rad, and the height stays at the
// analytic rest height (groundRestDepth, 4 corners) within 1e-7 m.
TEST(Stability, RestingBoxGainsNoEnergyAndDoesNotDriftFor100kSteps) {
  const double k = 2000.0, mass = 1.0, halfHeight = 0.05;
  const Scene scene = test::sceneFromText(
      R"({ "timestep": 0.001, "sleeping": false, "effects": ["gravity", "ground", "damping", "rotation"],
           "contact": { "mode": "penalty", "stiffness": 2000.0, "damping": 5.0, "direction": "field_gradient" }, "bodies": [ )" +
      boxBody("box", 0.1, halfHeight, 0.1, mass, 0.052) + " ] }");
  bullet::SceneWorld world(scene);
  ASSERT_EQ(world.model(0).shell().size(), 8u);
  constexpr int kSettle = 2000;
  for (int f = 0; f < kSettle; ++f) world.step();
  const double settledEnergy = mechanicalEnergy(world);
  const bullet::SceneBodyState settled = world.bodyState(0);
  double maxEnergyRise = -1e300, maxDrift = 0.0, maxYaw = 0.0, minY = 1e300, maxY = -1e300;
  for (int f = kSettle; f < kRestingSteps; ++f) {
    world.step();
    const bullet::SceneBodyState s = world.bodyState(0);
    maxEnergyRise = std::max(maxEnergyRise, mechanicalEnergy(world) - settledEnergy);
    maxDrift = std::max(maxDrift, std::hypot(s.position.x(), s.position.z()));
    maxYaw = std::max(maxYaw, std::abs(yawOf(s.orientation)));
    minY = std::min(minY, s.position.y());
    maxY = std::max(maxY, s.position.y());
  }
  std::printf("rest: energy rise %.3g J, drift %.3g m, yaw %.3g rad, y in [%.9f, %.9f], settled y %.9f\n",
              maxEnergyRise, maxDrift, maxYaw, minY, maxY, settled.position.y());
  const double expected = halfHeight - groundRestDepth(mass * kGravity, 4, k, 5.0, 0.001);
  EXPECT_LE(maxEnergyRise, 1e-6);
  EXPECT_LE(maxDrift, 1e-6);
  EXPECT_LE(maxYaw, 1e-6);
  EXPECT_NEAR(minY, expected, 1e-7);
  EXPECT_NEAR(maxY, expected, 1e-7);
  EXPECT_FALSE(world.hasNonFinite());
  EXPECT_TRUE(world.tunneledBodies().empty());
}

// Three boxes, each smaller than the one below (so the corners of each box press on the middle of the top
// face below it, where the box's field is the exact plane distance), rest at their analytic heights: box i's
// bottom corners carry the weight of box i and everything above it, d_i = (n - i) m g / (4 k) (box 0 on the
// ground: groundRestDepth; the boxes above move with the same predicted motion, so no correction). They stay
// stacked (no horizontal drift, no yaw) and the energy does not rise after settling.
TEST(Stability, StackOfThreeBoxesRestsAtAnalyticHeights) {
  const double k = 4000.0, mass = 1.0, h = 0.04;
  const double halfWidths[3] = {0.15, 0.10, 0.06};
  std::string bodies;
  for (int i = 0; i < 3; ++i) {
    bodies += (i ? ", " : "") + boxBody("box" + std::to_string(i), halfWidths[i], h, halfWidths[i], mass,
                                        h + 2 * h * i + 0.001 * (i + 1));
  }
  const Scene scene = test::sceneFromText(
      R"({ "timestep": 0.001, "sleeping": false, "effects": ["gravity", "ground", "damping", "rotation"],
           "contact": { "mode": "penalty", "stiffness": 4000.0, "damping": 5.0, "direction": "field_gradient" }, "bodies": [ )" +
      bodies + " ] }");
  bullet::SceneWorld world(scene);
  // Settled: the slowest mode (rocking of the stack) has decayed below 1e-11 J of kinetic energy by then.
  for (int f = 0; f < 5000; ++f) world.step();
  const double settledEnergy = mechanicalEnergy(world);
  double maxEnergyRise = -1e300, maxDrift = 0.0, maxYaw = 0.0;
  for (int f = 0; f < 10000; ++f) {
    world.step();
    maxEnergyRise = std::max(maxEnergyRise, mechanicalEnergy(world) - settledEnergy);
    for (int i = 0; i < 3; ++i) {
      const bullet::SceneBodyState s = world.bodyState(i);
      maxDrift = std::max(maxDrift, std::hypot(s.position.x(), s.position.z()));
      maxYaw = std::max(maxYaw, std::abs(yawOf(s.orientation)));
    }
  }
  double expected = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double depth =
        i == 0 ? groundRestDepth(3 * mass * kGravity, 4, k, 5.0, 0.001) : (3 - i) * mass * kGravity / (4 * k);
    expected += (i == 0 ? h : 2 * h) - depth;
    std::printf("stack: box%d y %.9f expected %.9f\n", i, world.bodyState(i).position.y(), expected);
    EXPECT_NEAR(world.bodyState(i).position.y(), expected, 1e-6) << "box" << i;
  }
  std::printf("stack: energy rise %.3g J, drift %.3g m, yaw %.3g rad\n", maxEnergyRise, maxDrift, maxYaw);
  EXPECT_LE(maxEnergyRise, 1e-6);
  EXPECT_LE(maxDrift, 1e-6);
  EXPECT_LE(maxYaw, 1e-6);
  EXPECT_FALSE(world.hasNonFinite());
  EXPECT_TRUE(world.tunneledBodies().empty());
}

// Mass ratio 1:1000, both ways: a 1 kg box on a 1 g box and the reverse, on the ground, started at their
// analytic rest heights (the lower box's corners carry both weights). The rest state is kept: neither box
// moves more than 1e-6 m from it, nothing tunnels, nothing is NaN.
void expectMassRatioRests(double lowerMass, double upperMass, double timestep, double damping, int steps) {
  const double k = 4000.0, h = 0.04;
  const double lowerY = h - groundRestDepth((lowerMass + upperMass) * kGravity, 4, k, damping, timestep);
  const double upperY = lowerY + 2 * h - upperMass * kGravity / (4 * k);
  const std::string bodies =
      boxBody("lower", 0.15, h, 0.15, lowerMass, lowerY) + ", " + boxBody("upper", 0.08, h, 0.08, upperMass, upperY);
  char contact[160];
  std::snprintf(
      contact, sizeof contact,
      R"("contact": { "mode": "penalty", "stiffness": %.17g, "damping": %.17g, "direction": "field_gradient" })", k,
      damping);
  const Scene scene =
      test::sceneFromText(R"({ "timestep": )" + std::to_string(timestep) +
                          R"(, "sleeping": false, "effects": ["gravity", "ground", "damping", "rotation"], )" +
                          contact + R"(, "bodies": [ )" + bodies + " ] }");
  bullet::SceneWorld world(scene);
  double maxDeviation = 0.0;
  for (int f = 0; f < steps; ++f) {
    world.step();
    ASSERT_FALSE(world.hasNonFinite()) << "frame " << f;
    maxDeviation = std::max({maxDeviation, (world.bodyState(0).position - Vec3(0, lowerY, 0)).norm(),
                             (world.bodyState(1).position - Vec3(0, upperY, 0)).norm()});
  }
  std::printf("mass ratio %g:%g: lower %.9f (%.9f) upper %.9f (%.9f) max deviation %.3g m\n", lowerMass, upperMass,
              world.bodyState(0).position.y(), lowerY, world.bodyState(1).position.y(), upperY, maxDeviation);
  EXPECT_LT(maxDeviation, 1e-6);
  EXPECT_TRUE(world.tunneledBodies().empty());
  EXPECT_LT(world.bodyState(0).linearVelocity.norm() + world.bodyState(1).linearVelocity.norm(), 1e-4);
}

// The penalty springs and dampers are explicit: the light box needs omega dt < 2 with omega = sqrt(n k / m)
// over the n shell points that hold it (8 when it is sandwiched: sqrt(8 * 4000 / 0.001) = 5657 rad/s), and
// n c dt / m < 2 for its damping, for rotation too (where n counts about 3x more: the corners' arms are long
// for the box's small inertia). At dt = 1 ms (omega dt = 5.7) the light box is thrown off (measured: 767 m
// away, no NaN); with dt = 0.1 ms and c = 1 N s/m it spins up about its axis (rotational damping 2.3 > 2);
// with dt = 0.1 ms and c = 0.25 N s/m (omega dt = 0.57, rotational damping 0.6) it rests.
// The heavy-on-light stack is checked for 0.5 s only: without friction it is physically unstable. A tilt of
// the light box by theta turns the heavy box's weight into a sideways push m_h g theta on the light box, and
// an offset x of the load tilts it by theta = m_h g x / K (K = 4 k a^2 = 360 N m/rad, the ground corners'
// rotational stiffness): the light box is squeezed out at the rate sqrt((m_h g)^2 / (K m_l)) = 16 /s (measured
// 16 /s, growing from float noise to 1e-6 m after ~1.5 s). Friction would hold it, but regularized friction
// on a 1 g body needs dt < 4 us (viscous coefficient mu m_h g / frictionSlipSpeed = 490 N s/m).
TEST(Stability, HeavyBoxOnLightBoxRests) {
  expectMassRatioRests(0.001, 1.0, 0.0001, 0.25, 5000);
}

TEST(Stability, LightBoxOnHeavyBoxRests) {
  expectMassRatioRests(1.0, 0.001, 0.0001, 0.25, 20000);
}

// A box hits the analytic ground at 1 to 100 of its cells per step (gravity on). The time-of-impact clamp
// and the penalty forces stop it: its centre never goes below the ground (at most a cell's worth of
// penetration of its corners), and kinetic + potential energy never rises above the energy at launch.
TEST(Stability, FastBoxIntoTheGroundDoesNotTunnelAndGainsNoEnergy) {
  for (const double cellsPerStep : {1.0, 10.0, 30.0, 100.0}) {
    const double h = 0.05;
    const Scene scene = test::sceneFromText(
        R"({ "timestep": 0.001, "sleeping": false, "effects": ["gravity", "ground", "damping", "rotation"],
             "contact": { "mode": "penalty", "stiffness": 2000.0, "damping": 5.0, "direction": "field_gradient" }, "bodies": [ )" +
        boxBody("box", 0.1, h, 0.1, 1.0, 0.0) + " ] }");
    bullet::SceneWorld probe(scene);
    const double cell = probe.model(0).cellSize();
    const double speed = cellsPerStep * cell / scene.timestep;  // m/s
    Scene launched = scene;
    launched.bodies[0].position.y() = h + 2.5 * cellsPerStep * cell + 0.01;
    launched.bodies[0].velocity = Vec3(0, -speed, 0);
    bullet::SceneWorld world(launched);
    const double launchEnergy = mechanicalEnergy(world);
    double maxEnergy = -1e300, minY = 1e300, maxPenetrationCells = 0.0;
    for (int f = 0; f < 1500; ++f) {
      world.step();
      ASSERT_FALSE(world.hasNonFinite()) << cellsPerStep << " cells/step, frame " << f;
      maxEnergy = std::max(maxEnergy, mechanicalEnergy(world));
      minY = std::min(minY, world.bodyState(0).position.y());
      maxPenetrationCells = std::max(maxPenetrationCells, world.lastFrame().penetrationCells);
    }
    std::printf(
        "ground %5.1f cells/step (%.1f m/s): energy max %.6g of %.6g J, min y %.5f, pen %.2f cells, "
        "clamps %lld, final y %.6f\n",
        cellsPerStep, speed, maxEnergy, launchEnergy, minY, maxPenetrationCells, static_cast<long long>(world.clamps()),
        world.bodyState(0).position.y());
    EXPECT_TRUE(world.tunneledBodies().empty()) << cellsPerStep;
    EXPECT_GT(minY, h - cell) << cellsPerStep;
    // 1e-6: Bullet stores velocities in float (the launch energy itself is known to ~1e-7).
    EXPECT_LE(maxEnergy, launchEnergy + 1e-6 * std::abs(launchEnergy)) << cellsPerStep;
    EXPECT_NEAR(world.bodyState(0).position.y(), h - groundRestDepth(kGravity, 4, 2000.0, 5.0, 0.001), 1e-6)
        << cellsPerStep;
  }
}

// A box shot at a thin static plate (3 cm, 2 plate cells thick) at 1 to 100 plate cells per step, no
// gravity: it stays on its side of the plate and its kinetic energy never exceeds the launch energy.
TEST(Stability, FastBoxIntoAThinPlateDoesNotTunnelAndGainsNoEnergy) {
  for (const double cellsPerStep : {1.0, 10.0, 30.0, 100.0}) {
    const Scene scene = test::sceneFromText(
        R"({ "timestep": 0.001, "sleeping": false, "effects": ["damping", "rotation"],
             "contact": { "mode": "penalty", "stiffness": 2000.0, "damping": 2.0, "direction": "field_gradient" }, "bodies": [
             { "name": "plate", "primitive": { "type": "box", "half_extents": [0.3, 0.015, 0.3] }, "static": true,
               "points": 600, "resolution": 40 }, )" +
        boxBody("box", 0.05, 0.05, 0.05, 1.0, 1.0) + " ] }");
    bullet::SceneWorld probe(scene);
    const double cell = probe.model(0).cellSize();
    const double speed = cellsPerStep * cell / scene.timestep;
    Scene launched = scene;
    launched.bodies[1].position.y() = 0.015 + 0.05 + 2.5 * cellsPerStep * cell + 0.01;
    launched.bodies[1].velocity = Vec3(0, -speed, 0);
    bullet::SceneWorld world(launched);
    const double launchEnergy = world.kineticEnergy();
    double maxEnergy = 0.0, minY = 1e300;
    for (int f = 0; f < 300; ++f) {
      world.step();
      ASSERT_FALSE(world.hasNonFinite()) << cellsPerStep << " cells/step, frame " << f;
      maxEnergy = std::max(maxEnergy, world.kineticEnergy());
      minY = std::min(minY, world.bodyState(1).position.y());
    }
    std::printf("plate %5.1f cells/step (%.1f m/s): energy max %.6g of %.6g J, min y %.5f, clamps %lld\n", cellsPerStep,
                speed, maxEnergy, launchEnergy, minY, static_cast<long long>(world.clamps()));
    EXPECT_TRUE(world.tunneledBodies().empty()) << cellsPerStep;
    EXPECT_GT(minY, 0.015 + 0.05 - cell) << cellsPerStep;             // its bottom stays above the plate's mid-plane
    EXPECT_LE(maxEnergy, launchEnergy * (1 + 1e-6)) << cellsPerStep;  // float velocities
  }
}

// Two boxes start deeply interpenetrated (4 cm, about 3 cells, along every axis), no gravity: the penalty
// forces push them apart, and the kinetic energy they reach never exceeds the penalty energy stored at the
// start (the forces derive from that energy; damping only removes some). They end separated, no NaN.
TEST(Stability, DeeplyInterpenetratedBoxesSeparateWithoutEnergyGain) {
  const double k = 2000.0;
  const Scene scene = test::sceneFromText(
      R"({ "timestep": 0.001, "sleeping": false, "effects": ["damping", "rotation"],
           "contact": { "mode": "penalty", "stiffness": 2000.0, "damping": 2.0, "direction": "field_gradient" }, "bodies": [
           { "name": "a", "primitive": { "type": "box", "half_extents": [0.1, 0.1, 0.1] }, "mass": 1.0,
             "position": [0, 0, 0], "points": 150, "resolution": 16 },
           { "name": "b", "primitive": { "type": "box", "half_extents": [0.1, 0.1, 0.1] }, "mass": 1.0,
             "position": [0.16, 0.12, 0.1], "points": 150, "resolution": 16 } ] })");
  bullet::SceneWorld world(scene);
  const double stored = storedPenaltyEnergy(world, k);
  ASSERT_GT(stored, 0.01);
  double maxKinetic = 0.0;
  for (int f = 0; f < 1000; ++f) {
    world.step();
    ASSERT_FALSE(world.hasNonFinite()) << "frame " << f;
    maxKinetic = std::max(maxKinetic, world.kineticEnergy());
  }
  std::printf("interpenetrated: stored %.6g J, max kinetic %.6g J, final contacts %d, distance %.4f\n", stored,
              maxKinetic, world.lastFrame().contacts,
              (world.bodyState(1).position - world.bodyState(0).position).norm());
  EXPECT_GT(maxKinetic, 0.0);
  EXPECT_LE(maxKinetic, stored);
  EXPECT_EQ(world.lastFrame().contacts, 0);
  EXPECT_DOUBLE_EQ(storedPenaltyEnergy(world, k), 0.0);
  // Momentum: the pair started at rest and every impulse acts on both bodies.
  EXPECT_LT((world.bodyState(0).linearVelocity + world.bodyState(1).linearVelocity).norm(), 1e-4);
}

// Two identical boxes at exactly the same pose (each shell lies on the other's surface), and a small box
// entirely inside a large one (symmetric, deep): no NaN, kinetic energy bounded by the stored penalty energy
// (plus 1e-9 J for the coincident case, whose stored energy is the grid's interpolation error), and they
// either stay put (within 1 m) or end apart (no contact in the last step).
TEST(Stability, CoincidentAndNestedBodiesStayBounded) {
  const char* cases[] = {
      R"({ "name": "a", "primitive": { "type": "box", "half_extents": [0.1, 0.08, 0.06] }, "mass": 1.0,
           "points": 150, "resolution": 16 },
         { "name": "b", "primitive": { "type": "box", "half_extents": [0.1, 0.08, 0.06] }, "mass": 1.0,
           "points": 150, "resolution": 16 })",
      R"({ "name": "a", "primitive": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 1.0,
           "points": 150, "resolution": 16 },
         { "name": "b", "primitive": { "type": "sphere", "radius": 0.05, "subdivisions": 2 }, "mass": 1.0,
           "points": 100, "resolution": 16 })",
  };
  for (const char* bodies : cases) {
    const Scene scene =
        test::sceneFromText(std::string(R"({ "timestep": 0.001, "sleeping": false, "effects": ["damping", "rotation"],
             "contact": { "mode": "penalty", "stiffness": 2000.0, "damping": 2.0, "direction": "field_gradient" }, "bodies": [ )") +
                            bodies + " ] }");
    bullet::SceneWorld world(scene);
    const double stored = storedPenaltyEnergy(world, 2000.0);
    double maxKinetic = 0.0, maxDistance = 0.0;
    for (int f = 0; f < 1000; ++f) {
      world.step();
      ASSERT_FALSE(world.hasNonFinite()) << "frame " << f;
      maxKinetic = std::max(maxKinetic, world.kineticEnergy());
      for (int i = 0; i < 2; ++i) maxDistance = std::max(maxDistance, world.bodyState(i).position.norm());
    }
    std::printf("coincident/nested: stored %.6g J, max kinetic %.6g J, max distance %.6g m\n", stored, maxKinetic,
                maxDistance);
    EXPECT_LE(maxKinetic, stored + 1e-9);
    EXPECT_TRUE(maxDistance < 1.0 || world.lastFrame().contacts == 0) << maxDistance;
  }
}

// Why the stability scenes use "direction": "field_gradient": with the paper's shell-normal direction
// (the default), the corners of a box resting on the ground have vertex normals that point sideways, so
// the ground pushes them sideways, and the box slides off and gains energy; with the field's gradient the
// same box stays put. (Measured over 3 s: shell normals ~0.9 m of drift and 0.19 J of kinetic energy.)
TEST(Stability, ShellNormalForceDirectionDriftsWhereFieldGradientRests) {
  auto run = [](const std::string& direction) {
    const Scene scene = test::sceneFromText(
        R"({ "timestep": 0.001, "sleeping": false, "effects": ["gravity", "ground", "damping", "rotation"],
             "contact": { "mode": "penalty", "stiffness": 2000.0, "damping": 5.0, "direction": ")" +
        direction + R"(" }, "bodies": [ )" + boxBody("box", 0.1, 0.05, 0.1, 1.0, 0.052) + " ] }");
    bullet::SceneWorld world(scene);
    for (int f = 0; f < 3000; ++f) world.step();
    return std::make_pair(std::hypot(world.bodyState(0).position.x(), world.bodyState(0).position.z()),
                          world.kineticEnergy());
  };
  const auto [gradientDrift, gradientEnergy] = run("field_gradient");
  const auto [normalDrift, normalEnergy] = run("shell_normal");
  std::printf("3 s at rest: field_gradient drift %.3g m, KE %.3g J; shell_normal drift %.3g m, KE %.3g J\n",
              gradientDrift, gradientEnergy, normalDrift, normalEnergy);
  EXPECT_LT(gradientDrift, 1e-6);
  EXPECT_LT(gradientEnergy, 1e-9);
  EXPECT_GT(normalDrift, 0.1);
  EXPECT_GT(normalEnergy, 0.01);  // more than the 1 mJ of potential energy of its 2 mm drop
}

}  // namespace stability_test
}  // namespace sdfccd
