/// @file
/// @brief Several obstacles, static or moving, each a field or a point shell (haptic_obstacles.h), against analytic
/// answers: a tool between two static walls (both methods), a moving wall pushing the tool (the god-object rides on the
/// wall at sigma, never inside; the penalty object's velocity follows the wall's), a shell obstacle against the tool's
/// field giving the mirror of the field-vs-shell setup (forces, torques, rows), the constraint method never penetrating
/// a moving shell obstacle, and the least-distance push.
#include "sdfccd/haptics/haptic_obstacles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include "sdfccd/error.h"
#include "sdfccd/haptics/god_object.h"
#include "sdfccd/haptics/haptic_scene.h"
#include "sdfccd/haptics/least_distance.h"
#include "sdfccd/haptics/penalty_renderer.h"
#include "sdfccd/haptics/virtual_coupling.h"
#include "sdfccd/shell/analytic_shells.h"

namespace sdfccd::haptics {
namespace {

constexpr double kHalf = 0.01;  // the tool's half size (m)
constexpr double kWall = 0.03;  // the walls' distance from the origin (m)

Rigid translation(const Vec3& t) {
  Rigid r = Rigid::Identity();
  r.translation() = t;
  return r;
}

/// A slab tool: a 5 x 5 grid of points on each of its faces x = +-kHalf, normals +-x (so every point on a face
/// carries the same depth against a wall x = const).
std::shared_ptr<const PointTree> slabTool() {
  PointShell shell;
  for (const double side : {-1.0, 1.0})
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j) {
        shell.positions.emplace_back(side * kHalf, -kHalf + 0.5 * kHalf * i, -kHalf + 0.5 * kHalf * j);
        shell.normals.emplace_back(side, 0.0, 0.0);
      }
  return std::make_shared<const PointTree>(std::move(shell));
}

/// A wall x = x0 whose solid side is `solidSide` (-1: x < x0), along an optional keyframed path (the plane is
/// x_local = 0 in its frame; the path moves that frame).
HapticObstacle wall(double solidSide, const std::vector<PoseKeyframe>& keys, double x0 = 0.0) {
  HapticObstacle o;
  o.plane.emplace(Vec3(-solidSide, 0.0, 0.0), 0.0);
  o.cellSize = 1e-3;
  o.path.worldFromObstacle = translation(Vec3(x0, 0.0, 0.0));
  if (!keys.empty()) o.path.keys = UserScript(keys);
  return o;
}

GodObjectSettings godSettings() {
  GodObjectSettings s;
  s.mass = 0.05;
  s.inertiaDiagonal = Vec3::Constant(2e-6);
  s.sigma = 2e-5;
  s.contactThreshold = 5e-5;
  s.slideFloor = 1e-5;
  s.sinkTolerance = 1e-7;
  s.maxStepTranslation = 2e-3;
  s.renderStiffness = 300.0;
  return s;
}

/// The smallest phi over the tool's points against a wall obstacle at the tool's pose (the obstacle at `wallPose`).
double clearance(const PointTree& tree, const HapticObstacle& w, const Rigid& wallPose, const Rigid& tool) {
  double least = 1e300;
  for (const Vec3& p : tree.shell().positions)
    least = std::min(least, w.plane->distance(wallPose.inverse() * (tool * p)));
  return least;
}

TEST(HapticObstacles, GodObjectStopsAtEitherOfTwoStaticWalls) {
  const auto tree = slabTool();
  const std::vector<HapticObstacle> walls = {wall(-1.0, {}, -kWall), wall(1.0, {}, kWall)};
  ObstacleContacts obstacles(walls, *tree, nullptr);
  const GodObjectSettings s = godSettings();
  GodObject god(std::move(obstacles), Rigid::Identity(), s);
  for (const double side : {1.0, -1.0}) {
    const Rigid device = translation(Vec3(side * 0.05, 0.0, 0.0));
    GodObjectStepResult r;
    for (int cycle = 0; cycle < 300; ++cycle) {
      r = god.step(device);
      for (const HapticObstacle& w : walls)
        ASSERT_GE(clearance(*tree, w, w.path.worldFromObstacle, god.pose()), 0.0) << "cycle " << cycle;
    }
    // Analytic: the face stops on the contact level set sigma of the wall, x = +-(wall - half - sigma).
    const double x = god.pose().translation().x();
    EXPECT_NEAR(x, side * (kWall - kHalf - s.sigma), 0.1 * s.sigma) << side;
    EXPECT_NEAR(god.pose().translation().y(), 0.0, 1e-12);
    // F = k_render (god - device) along x.
    EXPECT_NEAR(r.wrenchOnDevice.x(), s.renderStiffness * (x - side * 0.05), 1e-6 * s.renderStiffness * 0.05);
    EXPECT_EQ(r.nextContactCount, 25);  // one face's points
  }
}

PenaltyRendererSettings penaltySettings() {
  PenaltyRendererSettings p;
  p.mass = 0.05;
  p.inertiaDiagonal = Vec3::Constant(2e-6);
  p.contact.stiffness = 200.0;
  p.coupling.linearStiffness = 2000.0;
  p.coupling.linearDamping = 10.0;
  p.coupling.maxDisplacement = 5e-4;
  return p;
}

TEST(HapticObstacles, PenaltyRestsAgainstEitherOfTwoStaticWalls) {
  const auto tree = slabTool();
  const std::vector<HapticObstacle> walls = {wall(-1.0, {}, -kWall), wall(1.0, {}, kWall)};
  ObstacleContacts obstacles(walls, *tree, nullptr);
  const PenaltyRendererSettings p = penaltySettings();
  PenaltyRenderer renderer(std::move(obstacles), Rigid::Identity(), p);
  for (const double side : {1.0, -1.0}) {
    RigidBodyState device;
    device.worldFromBody = translation(Vec3(side * 0.05, 0.0, 0.0));
    PenaltyStepResult r;
    for (int tick = 0; tick < 3000; ++tick) {
      renderer.setObstacleTime(1e-3 * tick);
      r = renderer.step(device);
    }
    // At rest on one face: 25 points at the same depth d carry 25 k d, which balances the saturated coupling
    // (k_c x_max = 1 N): d = 1 / (25 * 200) = 0.2 mm.
    const double x = renderer.state().worldFromBody.translation().x();
    const double depth = side * x + kHalf - kWall;
    EXPECT_NEAR(depth, p.coupling.linearStiffness * p.coupling.maxDisplacement / (25 * p.contact.stiffness), 1e-6);
    EXPECT_NEAR(r.contactWrench.x(), -side * 25 * p.contact.stiffness * depth, 1e-6);
    EXPECT_EQ(r.contactCount, 25);
    EXPECT_LT(renderer.state().linearVelocity.norm(), 1e-4);
  }
}

/// The left wall sweeps from x = -kWall to +kWall - 2 kHalf at 0.05 m/s (t in [0, 0.8]), then stays.
std::vector<HapticObstacle> sweepingWall() {
  return {wall(-1.0, {{0.0, translation(Vec3(-kWall, 0, 0))}, {0.8, translation(Vec3(kWall - 2 * kHalf, 0, 0))}})};
}

TEST(HapticObstacles, MovingWallPushesTheGodObjectWithoutPenetrating) {
  const auto tree = slabTool();
  const std::vector<HapticObstacle> walls = sweepingWall();
  ObstacleContacts obstacles(walls, *tree, nullptr);
  const GodObjectSettings s = godSettings();
  GodObject god(std::move(obstacles), Rigid::Identity(), s);
  const Rigid device = Rigid::Identity();  // the user holds the device where the tool started
  for (int cycle = 0; cycle <= 1000; ++cycle) {
    const double t = 1e-3 * cycle;
    god.setObstacleTime(t);
    const GodObjectStepResult r = god.step(device);
    const Rigid wallPose = walls[0].path.poseAt(t);
    ASSERT_GE(clearance(*tree, walls[0], wallPose, god.pose()), 0.0) << "t = " << t;
    const double wallX = wallPose.translation().x();
    const double x = god.pose().translation().x();
    if (wallX > -kHalf + 1e-4) {
      // Analytic: the tool rides on the wall's contact level set, and the device feels k (god - device).
      ASSERT_NEAR(x, wallX + kHalf + s.sigma, 0.5 * s.contactThreshold) << "t = " << t;
      ASSERT_NEAR(r.wrenchOnDevice.x(), s.renderStiffness * x, 1e-6) << "t = " << t;
    } else if (wallX < -kHalf - 1e-3) {
      ASSERT_NEAR(x, 0.0, 1e-12) << "t = " << t;  // not reached yet
    }
  }
}

TEST(HapticObstacles, MovingWallCarriesThePenaltyObjectAtItsVelocity) {
  const auto tree = slabTool();
  const std::vector<HapticObstacle> walls = sweepingWall();
  ObstacleContacts obstacles(walls, *tree, nullptr);
  const PenaltyRendererSettings p = penaltySettings();
  PenaltyRenderer renderer(std::move(obstacles), Rigid::Identity(), p);
  RigidBodyState device;  // held at the start
  double deepest = 0.0;
  for (int tick = 0; tick < 800; ++tick) {
    renderer.setObstacleTime(1e-3 * tick);
    const PenaltyStepResult r = renderer.step(device);
    deepest = std::max(deepest, r.maxPenetration);
    if (tick >= 500) {  // the wall reached the tool at 0.4 s: the tool moves with it
      ASSERT_NEAR(renderer.state().linearVelocity.x(), 0.05, 0.005) << "tick " << tick;
      const double wallX = walls[0].path.poseAt(1e-3 * (tick + 1)).translation().x();
      // Pressed on the wall by the coupling at constant velocity: its 25 face points at depth d carry the coupling's
      // pull, 25 k d = |F_coupling|.
      const double pull = -couplingWrench(device, renderer.state(), p.coupling).onSimulation.x();
      const double depth = wallX - (renderer.state().worldFromBody.translation().x() - kHalf);
      ASSERT_NEAR(depth, pull / (25 * p.contact.stiffness), 2e-5) << "tick " << tick;
    }
  }
  EXPECT_LT(deepest, 5e-4);
}

/// A box tool's field (exact box distances sampled on a 1 mm grid), in the tool's body frame.
std::shared_ptr<const GridField> boxField() {
  CsgObstacle csg;
  CsgPrimitive box;
  box.halfExtents = Vec3::Constant(kHalf);
  csg.solids = {box};
  csg.spacing = 1e-3;
  return std::make_shared<const GridField>(sampleCsgObstacle(csg));
}

std::shared_ptr<const PointTree> ballShell() {
  AnalyticShellSettings a;
  a.spacing = 1e-3;
  return std::make_shared<const PointTree>(sphereShell(0.006, a));
}

Rigid pose(const Vec3& t, const Vec3& rotationVector) {
  Rigid r = translation(t);
  r.linear() = rotationFromVector(rotationVector);
  return r;
}

TEST(HapticObstacles, ShellObstacleAgainstToolFieldMirrorsFieldObstacleAgainstToolShell) {
  const auto field = boxField();
  const auto ball = ballShell();
  const Rigid worldFromBox = pose(Vec3(0.001, -0.002, 0.0), Vec3(0.0, 0.2, 0.05));
  const Rigid worldFromBall = pose(Vec3(0.002, 0.0125, 0.001), Vec3(0.3, 0.0, 0.1));
  // A: the tool is the box (its field), the obstacle the ball (its shell). B: the roles swapped.
  HapticObstacle ballObstacle;
  ballObstacle.shell = ball;
  ballObstacle.path.worldFromObstacle = worldFromBall;
  HapticObstacle boxObstacle;
  boxObstacle.grid = field;
  boxObstacle.path.worldFromObstacle = worldFromBox;
  const auto unused = slabTool();
  ObstacleContacts a({ballObstacle}, *unused, field.get());
  ObstacleContacts b({boxObstacle}, *ball, nullptr);
  ContactQuerySettings query;
  query.penalty.stiffness = 200.0;
  query.penalty.model = PenaltyModel::Discrete;
  query.discreteMode = CcdMode::FirstHit;
  ObstaclePenaltySum sumA, sumB;
  a.moveOver(0.0, 1e-3);
  b.moveOver(0.0, 1e-3);
  a.penalty(ShellMotion::fixed(worldFromBox), 1e-3, query, true, sumA);
  b.penalty(ShellMotion::fixed(worldFromBall), 1e-3, query, true, sumB);
  ASSERT_GT(sumA.contactCount, 5);
  EXPECT_EQ(sumA.contactCount, sumB.contactCount);
  const Vec3 forceB = sumB.wrenchOnTool.head<3>();
  ASSERT_GT(forceB.norm(), 0.05);
  EXPECT_LT((sumA.wrenchOnTool.head<3>() + forceB).norm(), 1e-9 * forceB.norm());
  // Torques about each tool's centre: tau_A + tau_B = (c_A - c_B) x F_B.
  const Vec3 expected = (worldFromBox.translation() - worldFromBall.translation()).cross(forceB);
  EXPECT_LT((sumA.wrenchOnTool.tail<3>() + sumB.wrenchOnTool.tail<3>() - expected).norm(), 1e-9 * forceB.norm() * 0.02);
  EXPECT_NEAR(sumA.maxPenetration, sumB.maxPenetration, 1e-12);
  // The constraint rows: the same points, opposite normals, handles from each tool's centre.
  GodObjectSettings s = godSettings();
  s.contactThreshold = 1e-4;
  GodObjectStepResult out;
  std::vector<GodObjectContact> rowsA, rowsB;
  a.discreteCandidates(worldFromBox, s, out);
  a.appendContacts(worldFromBox, s, rowsA, out);
  b.discreteCandidates(worldFromBall, s, out);
  b.appendContacts(worldFromBall, s, rowsB, out);
  ASSERT_EQ(rowsA.size(), rowsB.size());
  ASSERT_GT(rowsA.size(), 5u);
  for (std::size_t k = 0; k < rowsA.size(); ++k) {
    EXPECT_EQ(rowsA[k].point, rowsB[k].point);
    EXPECT_LT((rowsA[k].normalIntoObstacle + rowsB[k].normalIntoObstacle).norm(), 1e-9);
    EXPECT_LT((rowsA[k].handle - rowsB[k].handle - (worldFromBall.translation() - worldFromBox.translation())).norm(),
              1e-12);
  }
}

/// The discrete penalty wrench on the tool (a box field) from the ball shell at `worldFromBall`, the tool at `tool`.
Vec6 ballOnBoxWrench(ObstacleContacts& contacts, const Rigid& tool, ObstaclePenaltySum& sum) {
  ContactQuerySettings query;
  query.penalty.stiffness = 200.0;
  query.penalty.model = PenaltyModel::Discrete;
  query.discreteMode = CcdMode::FirstHit;
  contacts.moveOver(0.0, 1e-3);
  contacts.penalty(ShellMotion::fixed(tool), 1e-3, query, true, sum);
  return sum.wrenchOnTool;
}

TEST(HapticObstacles, ShellObstaclePenaltyGradientMatchesFiniteDifferences) {
  // A ball shell pressed into the top face of the tool's box field (a flat region of the field, where its trilinear
  // interpolation is exact): the force on each obstacle point follows its own (fixed) normal, so d(wrench on the
  // tool)/d(tool pose) has no dropped term and must match central differences.
  const auto field = boxField();
  HapticObstacle ball;
  ball.shell = ballShell();
  ball.path.worldFromObstacle = pose(Vec3(0.0005, 0.0152, -0.0003), Vec3(0.2, 0.1, 0.0));
  const auto unused = slabTool();
  ObstacleContacts contacts({ball}, *unused, field.get());
  const Rigid tool = pose(Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, 0.02));
  ObstaclePenaltySum at;
  ballOnBoxWrench(contacts, tool, at);
  ASSERT_GT(at.contactCount, 3);
  Mat6 fd;
  for (int j = 0; j < 6; ++j) {
    const double step = j < 3 ? 1e-7 : 1e-5;
    Vec6 dx = Vec6::Zero();
    dx[j] = step;
    ObstaclePenaltySum plus, minus;
    fd.col(j) = (ballOnBoxWrench(contacts, displacePose(tool, dx), plus) -
                 ballOnBoxWrench(contacts, displacePose(tool, -dx), minus)) /
                (2 * step);
    ASSERT_EQ(plus.contactCount, at.contactCount);  // no point crossed the surface
  }
  EXPECT_LT((fd - at.gradient).norm(), 1e-4 * at.gradient.norm()) << "fd\n" << fd << "\nanalytic\n" << at.gradient;
}

TEST(HapticObstacles, RotatingPaddleNeverPenetratesTheConstraintTool) {
  // A wall hinged 40 mm below the tool swings through 60 degrees in 0.5 s and sweeps the held tool aside: its
  // surface moves on arcs, so the push's first-order rows are corrected by the second round and the margin sigma.
  const auto tree = slabTool();
  HapticObstacle paddle;
  paddle.plane.emplace(Vec3(1.0, 0.0, 0.0), 0.0);  // solid x < 0 in the paddle's frame
  paddle.cellSize = 1e-3;
  const Vec3 hinge(-0.02, -0.04, 0.0);
  std::vector<PoseKeyframe> keys;
  for (int k = 0; k <= 10; ++k) {
    const double angle = -0.5 + 0.1 * k;  // rad about -z: the wall's top swings towards +x
    keys.push_back({0.05 * k, pose(hinge, Vec3(0.0, 0.0, -angle))});
  }
  paddle.path.keys = UserScript(keys);
  ObstacleContacts obstacles({paddle}, *tree, nullptr);
  GodObject god(std::move(obstacles), Rigid::Identity(), godSettings());
  for (int cycle = 0; cycle <= 600; ++cycle) {
    const double t = 1e-3 * cycle;
    god.setObstacleTime(t);
    god.step(Rigid::Identity());
    ASSERT_GE(clearance(*tree, paddle, paddle.path.poseAt(t), god.pose()), 0.0) << "t = " << t;
  }
  EXPECT_GT(god.pose().translation().x(), 0.005);  // swept aside
}

TEST(HapticObstacles, MovingShellObstacleNeverPenetratesTheConstraintTool) {
  // The tool carries a box field; a ball shell sweeps through where the tool starts, pushing it aside.
  const auto field = boxField();
  const auto unusedShell = slabTool();
  HapticObstacle ball;
  ball.shell = ballShell();
  ball.path.keys =
      UserScript({{0.0, translation(Vec3(-0.03, 0.004, 0.002))}, {0.6, translation(Vec3(0.03, 0.004, 0.002))}});
  ObstacleContacts obstacles({ball}, *unusedShell, field.get());
  GodObject god(std::move(obstacles), Rigid::Identity(), godSettings());
  double pushed = 0.0;
  for (int cycle = 0; cycle <= 700; ++cycle) {
    const double t = 1e-3 * cycle;
    god.setObstacleTime(t);
    god.step(Rigid::Identity());
    const Rigid toolFromBall = god.pose().inverse() * ball.path.poseAt(t);
    for (const Vec3& p : ball.shell->shell().positions)
      ASSERT_GE(field->distance(toolFromBall * p), 0.0) << "t = " << t;
    pushed = std::max(pushed, god.pose().translation().x());
  }
  EXPECT_GT(pushed, 0.005);  // it was pushed, not passed through
}

TEST(HapticObstacles, WallsClosingInPinchTheGodObjectWithoutNaN) {
  // The right wall stands at x = 15 mm; the left one closes from -30 mm to -5 mm: the 20 mm tool fits until the
  // gap is 20 mm + 2 sigma, then no push clears both: squeezed, and the god-object stays finite.
  const auto tree = slabTool();
  const std::vector<HapticObstacle> walls = {
      wall(-1.0, {{0.0, translation(Vec3(-kWall, 0, 0))}, {0.5, translation(Vec3(-0.005, 0, 0))}}),
      wall(1.0, {}, 0.015)};
  ObstacleContacts obstacles(walls, *tree, nullptr);
  const GodObjectSettings s = godSettings();
  GodObject god(std::move(obstacles), Rigid::Identity(), s);
  bool squeezed = false;
  double squeezedAt = 1.0;
  for (int cycle = 0; cycle <= 600; ++cycle) {
    const double t = 1e-3 * cycle;
    god.setObstacleTime(t);
    const GodObjectStepResult r = god.step(Rigid::Identity());
    ASSERT_TRUE(god.pose().matrix().allFinite());
    if (r.squeezed && !squeezed) squeezedAt = t;
    squeezed = squeezed || r.squeezed;
    if (!squeezed) {  // until pinched: clear of both walls
      for (const HapticObstacle& w : walls)
        ASSERT_GE(clearance(*tree, w, w.path.poseAt(t), god.pose()), 0.0) << "t = " << t;
    }
  }
  EXPECT_TRUE(squeezed);
  // The gap reaches 2 (kHalf + sigma) when the left wall is at 15 mm - 20 mm - 2 sigma: t = (0.025 - 2 sigma) / 0.05.
  EXPECT_NEAR(squeezedAt, (0.025 - 2 * s.sigma) / 0.05, 2e-3);
}

TEST(HapticObstacles, LeastDistanceMoveIsTheProjectionOntoTheHalfSpaces) {
  // Unit mass: min |p| subject to p_x <= -0.002 (a wall pushing along -x) and p_y <= 0.001: p = (-0.002, 0, 0).
  Mat6 mass = Mat6::Identity();
  ConstraintRows rows(2, 6);
  rows.row(0) = contactRow(Vec3::UnitX(), Vec3::Zero());
  rows.row(1) = contactRow(Vec3::UnitY(), Vec3::Zero());
  Eigen::VectorXd bound(2);
  bound << -0.002, 0.001;
  LeastDistanceResult r = leastDistanceMove(mass, rows, bound);
  ASSERT_TRUE(r.feasible);
  EXPECT_LT((r.move - (Vec6() << -0.002, 0, 0, 0, 0, 0).finished()).norm(), 1e-15);
  // Two walls squeezing: p_x <= -0.001 and -p_x <= -0.001 cannot both hold.
  rows.row(1) = contactRow(-Vec3::UnitX(), Vec3::Zero());
  bound << -0.001, -0.001;
  EXPECT_FALSE(leastDistanceMove(mass, rows, bound).feasible);
  // A heavier axis moves less: with mass 4 on x and 1 on y, min 4 px^2 + py^2 s.t. px + py <= -1: p = (-0.2, -0.8).
  mass(0, 0) = 4.0;
  ConstraintRows diagonal(1, 6);
  diagonal.row(0) << 1.0, 1.0, 0, 0, 0, 0;
  Eigen::VectorXd one(1);
  one << -1.0;
  r = leastDistanceMove(mass, diagonal, one);
  ASSERT_TRUE(r.feasible);
  EXPECT_NEAR(r.move[0], -0.2, 1e-12);
  EXPECT_NEAR(r.move[1], -0.8, 1e-12);
}

// Friction in the god-object is taken relative to the world: against a moving obstacle that would render the wrong
// tangential force, so the combination is refused in one line; a static obstacle with friction is fine.
TEST(HapticObstacles, GodObjectFrictionAgainstAMovingObstacleIsRefused) {
  const auto tree = slabTool();
  HapticObstacle wall;
  wall.plane.emplace(Vec3(0.0, 1.0, 0.0), 0.0);
  wall.cellSize = 1e-3;
  GodObjectSettings s = godSettings();
  s.qp.friction = 0.3;
  {
    ObstacleContacts still({wall}, *tree, nullptr);  // a temporary list: the obstacles are copied
    EXPECT_NO_THROW(GodObject(std::move(still), Rigid::Identity(), s));
  }
  std::vector<PoseKeyframe> keys = {{0.0, pose(Vec3(0.0, -0.01, 0.0), Vec3::Zero())},
                                    {1.0, pose(Vec3(0.01, -0.01, 0.0), Vec3::Zero())}};
  wall.path.keys = UserScript(keys);
  ObstacleContacts moving({wall}, *tree, nullptr);
  try {
    GodObject god(std::move(moving), Rigid::Identity(), s);
    ADD_FAILURE() << "friction against a moving obstacle was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("moving obstacle"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sdfccd::haptics
