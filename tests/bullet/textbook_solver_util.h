// Shared scenes of the solver-mode textbook suites (textbook_solver_test.cpp, textbook_solver_stack_test.cpp): boxes
// described by geometry, mass, friction and restitution, a world whose ground passes the body's values through Bullet's
// product rule, and the stand criterion (no centre moves more than 1 mm between t = 1 s and the end, penetration under
// 1 cell at the end).
#pragma once

#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bullet_test_util.h"
#include "sdfccd/bullet/scene_world.h"

namespace sdfccd::solver_textbook {

inline constexpr double kG = 9.81;
inline constexpr double kStep = 1.0 / 240.0;
inline constexpr double kHalf = 0.05;  // 10 cm boxes

struct BoxSpec {
  Vec3 position = Vec3::Zero();
  double mass = 1.0;
  double friction = 0.5;
  double restitution = 0.0;
  double half = kHalf;
};

inline std::string vec(const Vec3& v) {
  std::ostringstream s;
  s.precision(17);
  s << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}

inline std::string boxBody(const BoxSpec& b, int i) {
  std::ostringstream s;
  s << "{\"name\": \"box" << i << "\", \"primitive\": {\"type\": \"box\", \"half_extents\": [" << b.half << ", "
    << b.half << ", " << b.half << "]}, \"mass\": " << b.mass << ", \"friction\": " << b.friction
    << ", \"restitution\": " << b.restitution << ", \"position\": " << vec(b.position) << ", \"resolution\": 32}";
  return s.str();
}

inline std::string sceneText(const std::vector<std::string>& bodies, const Vec3& gravity, bool sleeping,
                             const std::string& mode = "solver") {
  std::ostringstream s;
  s << "{\"timestep\": " << kStep << ", \"gravity\": " << vec(gravity)
    << ", \"effects\": [\"gravity\", \"ground\", \"rotation\", \"friction\"], \"sleeping\": " << (sleeping ? "true" : "false")
    << ", \"contact\": {\"mode\": \"" << mode << "\"}, \"bodies\": [";
  for (std::size_t i = 0; i < bodies.size(); ++i) s << (i ? ", " : "") << bodies[i];
  s << "]}";
  return s.str();
}

/// A world of `text` whose ground takes friction 1 and restitution 1 (the pair's values are the body's).
inline std::unique_ptr<bullet::SceneWorld> makeWorld(const std::string& text, double timestep = kStep) {
  bullet::SceneWorldSettings settings;
  settings.timestep = timestep;
  settings.cacheDir = "textbook-model-cache";  // the bunny's field and shell (boxes are built, not cached)
  auto world = std::make_unique<bullet::SceneWorld>(test::sceneFromText(text), settings);
  btCollisionObject* ground = world->world().getCollisionObjectArray()[0];
  ground->setFriction(1.0);
  ground->setRestitution(1.0);
  return world;
}

inline Vec3 inclineGravity(double thetaDegrees) {
  const double t = thetaDegrees * kPi / 180.0;
  return Vec3(kG * std::sin(t), -kG * std::cos(t), 0.0);
}

/// Runs a scene of boxes for `seconds`: the largest centre motion between t = 1 s and the end, and the largest
/// penetration (cells) at the end.
struct StandResult {
  double maxMotion = 0;
  double endPenetrationCells = 0;
  bool allAsleep = false;
  bool finite = true;
};

inline StandResult stand(const std::vector<BoxSpec>& boxes, double seconds, double timestep = kStep,
                         bool sleeping = true) {
  std::vector<std::string> bodies;
  for (std::size_t i = 0; i < boxes.size(); ++i) bodies.push_back(boxBody(boxes[i], int(i)));
  auto world = makeWorld(sceneText(bodies, Vec3(0, -kG, 0), sleeping), timestep);
  std::vector<Vec3> at1;
  StandResult r;
  while (world->time() < seconds - 1e-9) {
    world->step();
    if (at1.empty() && world->time() >= 1.0 - 1e-9) {
      for (int i = 0; i < world->bodyCount(); ++i) at1.push_back(world->bodyState(i).position);
    }
  }
  for (int i = 0; i < world->bodyCount(); ++i) {
    r.maxMotion = std::max(r.maxMotion, (world->bodyState(i).position - at1[std::size_t(i)]).norm());
  }
  r.endPenetrationCells = world->lastFrame().penetrationCells;
  r.allAsleep = true;
  for (int i = 0; i < world->bodyCount(); ++i) {
    r.allAsleep = r.allAsleep && world->body(i).getActivationState() == ISLAND_SLEEPING;
  }
  r.finite = !world->hasNonFinite();
  return r;
}

inline std::vector<BoxSpec> column(int n, double mass = 1.0) {
  std::vector<BoxSpec> boxes;
  for (int i = 0; i < n; ++i) {
    BoxSpec b;
    b.mass = mass;
    b.position = Vec3(0, kHalf + i * (2 * kHalf + 0.001), 0);
    boxes.push_back(b);
  }
  return boxes;
}

inline void expectStands(const StandResult& r, const std::string& what) {
  // Printed on success too: the docs and the tests' comments quote these numbers.
  std::printf("  measured %s: largest centre motion %.4f mm after 1 s, end penetration %.3f cells, asleep %d\n",
              what.c_str(), 1e3 * r.maxMotion, r.endPenetrationCells, int(r.allAsleep));
  EXPECT_TRUE(r.finite) << what;
  EXPECT_LT(r.maxMotion, 1e-3) << what;
  EXPECT_LT(r.endPenetrationCells, 1.0) << what;
}

}  // namespace sdfccd::solver_textbook
