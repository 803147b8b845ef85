// Every Bullet shape against ours (bullet_shape_fields.h): cylinders, cones, convex hulls
// (any btConvexShape through its support points), static triangle meshes and terrain, compounds of them, and
// the announcement of a pair still unsupported. Answers are analytic: rest heights from the shapes' sizes
// (Bullet's margin included), no tunnelling through a zero-thickness wall at 20 m/s.
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bullet_test_util.h"
#include "bullet_world_fixture.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "sdfccd/mesh/procedural_meshes.h"

namespace sdfccd {
namespace other_shapes_test {

/// Settings of the given contact mode, defaults otherwise.
bullet::ContactSettings modeSettings(SdfccdContactMode mode) {
  bullet::ContactSettings settings;
  settings.mode = mode;
  return settings;
}

/// A dynamics world with our algorithms (solver mode by default, or penalty) and owned shapes, bodies, meshes,
/// terrain heights; it records what the contact system logs.
struct ShapesWorld : test::BulletTestWorld {
  std::vector<std::unique_ptr<btTriangleMesh>> meshes;
  std::vector<std::vector<float>> heights;
  std::vector<std::string> log;

  explicit ShapesWorld(SdfccdContactMode mode) : BulletTestWorld(modeSettings(mode)) {
    contacts->setLogCallback([this](const std::string& line) { log.push_back(line); });
  }
  /// A static btBvhTriangleMeshShape of `mesh` (its triangles as they are: one-sided or open).
  btRigidBody& addStaticMesh(const TriangleMesh& mesh) {
    meshes.push_back(std::make_unique<btTriangleMesh>());
    for (const auto& t : mesh.triangles) {
      auto v = [&](int i) {
        const Vec3& p = mesh.vertices[static_cast<std::size_t>(i)];
        return btVector3(btScalar(p.x()), btScalar(p.y()), btScalar(p.z()));
      };
      meshes.back()->addTriangle(v(t[0]), v(t[1]), v(t[2]));
    }
    return add(std::make_unique<btBvhTriangleMeshShape>(meshes.back().get(), true), 0.0, Vec3::Zero());
  }
  void run(int steps, double dt = 1.0 / 240.0) { step(steps, dt); }
};

/// Our box (10 cm cube), its model's cell size (m) and its lowest shell point in the world.
std::shared_ptr<const BodyModel> smallBox() {
  static const std::shared_ptr<const BodyModel> model =
      BodyModel::buildFromMesh(makeBox(Vec3(0.05, 0.05, 0.05)), test::smallModelSettings(24, 600, 1));
  return model;
}

double lowestShellPoint(const btRigidBody& body, const BodyModel& model) {
  double lowest = 1e300;
  for (const Vec3& p : model.shell().positions) {
    lowest = std::min(lowest, double(body.getWorldTransform()(bullet::toBtVector3(p)).y()));
  }
  return lowest;
}

/// Our box dropped 3 cm onto the static `ground` body whose top is at `top` comes to rest on it: its lowest
/// point within half a cell of the top, at rest, on top.
void expectBoxRestsOn(ShapesWorld& w, double top, const char* what) {
  const auto model = smallBox();
  btRigidBody& box = w.add(std::make_unique<bullet::SdfccdShape>(model), 1.0, Vec3(0.01, top + 0.05 + 0.03, -0.01));
  w.run(360);
  const double cell = model->cellSize();
  const double lowest = lowestShellPoint(box, *model);
  EXPECT_NEAR(lowest, top, 0.5 * cell) << what << ": cell " << cell;  // measured: within 0.2 mm
  EXPECT_LT(bullet::toVec3(box.getLinearVelocity()).norm(), 0.05) << what;
  EXPECT_LT(std::hypot(box.getWorldTransform().getOrigin().x() - 0.01, box.getWorldTransform().getOrigin().z() + 0.01),
            0.03)
      << what;
  EXPECT_EQ(w.contacts->statistics().unsupportedPairs, 0) << what;
  EXPECT_TRUE(w.log.empty()) << what;
}

class OtherShapes : public ::testing::TestWithParam<SdfccdContactMode> {};

// The bunny (0.2 m, default solver mode) dropped 2 cm onto a static btCylinderShape (top at y = 0.05) rests on
// its top: lowest shell point within a cell and the solver's margin, at rest, still over the cylinder.
TEST(OtherShapesBunny, BunnyRestsOnStaticCylinder) {
  const auto bunny = test::buildTestBunny(1500);
  ShapesWorld w(SdfccdContactMode::Solver);
  w.add(std::make_unique<btCylinderShape>(btVector3(0.3f, 0.05f, 0.3f)), 0.0, Vec3::Zero());
  const double lowest = -bunny->boundsInBody().min().y();
  btRigidBody& body = w.add(std::make_unique<bullet::SdfccdShape>(bunny), 1.0, Vec3(0.02, 0.05 + lowest + 0.02, -0.03));
  w.run(480);
  EXPECT_NEAR(lowestShellPoint(body, *bunny), 0.05, bunny->cellSize() + 0.002) << "cell " << bunny->cellSize();
  EXPECT_LT(bullet::toVec3(body.getLinearVelocity()).norm(), 0.05);
  EXPECT_LT(std::hypot(body.getWorldTransform().getOrigin().x(), body.getWorldTransform().getOrigin().z()), 0.2);
  EXPECT_EQ(w.contacts->statistics().unsupportedPairs, 0);
}

// Static cylinders (Y, and X lying on its side) and a cone's base; top heights from their sizes.
TEST_P(OtherShapes, BoxRestsOnStaticCylinder) {
  ShapesWorld w(GetParam());
  w.add(std::make_unique<btCylinderShape>(btVector3(0.3f, 0.05f, 0.3f)), 0.0, Vec3(0, 0, 0));
  expectBoxRestsOn(w, 0.05, "cylinder Y");
}

TEST_P(OtherShapes, BoxRestsOnCylinderLyingOnItsSide) {
  ShapesWorld w(GetParam());
  // btCylinderShapeX: half extents (half length, radius, radius); its top line is at y = radius. The box may
  // rock on the round top (a stable balance): at rest its shell touches the surface, sqrt(y^2 + z^2) = radius.
  w.add(std::make_unique<btCylinderShapeX>(btVector3(0.3f, 0.2f, 0.2f)), 0.0, Vec3(0, 0, 0));
  const auto model = smallBox();
  btRigidBody& box = w.add(std::make_unique<bullet::SdfccdShape>(model), 1.0, Vec3(0.01, 0.2 + 0.05 + 0.03, 0.0));
  w.run(720);
  double gap = 1e300;
  for (const Vec3& p : model->shell().positions) {
    const btVector3 q = box.getWorldTransform()(btVector3(btScalar(p.x()), btScalar(p.y()), btScalar(p.z())));
    gap = std::min(gap, std::hypot(double(q.y()), double(q.z())) - 0.2);
  }
  EXPECT_NEAR(gap, 0.0, model->cellSize() + 0.002);
  EXPECT_LT(bullet::toVec3(box.getLinearVelocity()).norm(), 0.05);
  EXPECT_GT(double(box.getWorldTransform().getOrigin().y()), 0.2);
  EXPECT_EQ(w.contacts->statistics().unsupportedPairs, 0);
}

TEST_P(OtherShapes, BoxRestsOnUpsideDownConeBase) {
  ShapesWorld w(GetParam());
  // A btConeShape points up (+y); btConeShapeZ with a rotation would do too. Here the cone's base faces up: a
  // cone of half height h has its base at y = -h, grown by its margin. The body is turned upside down.
  auto cone = std::make_unique<btConeShape>(btScalar(0.3), btScalar(0.2));
  const double baseDown = -double(cone->localGetSupportingVertex(btVector3(0, -1, 0)).y());
  btRigidBody& body = w.add(std::move(cone), 0.0, Vec3::Zero());
  btTransform flipped = body.getWorldTransform();
  flipped.setRotation(btQuaternion(btVector3(1, 0, 0), btScalar(M_PI)));
  body.setWorldTransform(flipped);
  expectBoxRestsOn(w, baseDown, "cone base");
}

// A convex hull of a box's eight corners behaves as the box: with margin 0 at the box's top, with Bullet's
// default margin 4 cm higher (a hull is its points grown by the margin).
TEST_P(OtherShapes, ConvexHullOfBoxBehavesAsTheBox) {
  for (double margin : {0.0, 0.04}) {
    ShapesWorld w(GetParam());
    auto hull = std::make_unique<btConvexHullShape>();
    for (int corner = 0; corner < 8; ++corner) {
      hull->addPoint(btVector3(corner & 1 ? 0.4f : -0.4f, corner & 2 ? 0.05f : -0.05f, corner & 4 ? 0.4f : -0.4f));
    }
    hull->setMargin(btScalar(margin));
    w.add(std::move(hull), 0.0, Vec3::Zero());
    expectBoxRestsOn(w, 0.05 + margin, margin == 0.0 ? "hull, margin 0" : "hull, margin 0.04");
  }
}

// The convex cache is keyed by content: a hull freed and another made (likely at the same address) with other
// points is not served the first one's field. Slab tops at 0.05 and then 0.12.
TEST_P(OtherShapes, FreedHullIsNotServedToItsSuccessor) {
  ShapesWorld w(GetParam());
  for (double top : {0.05, 0.12}) {
    auto hull = std::make_unique<btConvexHullShape>();
    for (int corner = 0; corner < 8; ++corner) {
      hull->addPoint(
          btVector3(corner & 1 ? 0.4f : -0.4f, btScalar(corner & 2 ? top : -0.05), corner & 4 ? 0.4f : -0.4f));
    }
    hull->setMargin(0);
    w.add(std::move(hull), 0.0, Vec3::Zero());
    expectBoxRestsOn(w, top, top < 0.1 ? "first hull" : "second hull");
    for (int i = 0; i < 2; ++i) {  // both bodies out, both shapes freed
      w.world.removeRigidBody(w.bodies.back().get());
      w.bodies.pop_back();
      w.shapes.pop_back();
    }
  }
}

// The other role: a dynamic cylinder, cone and multi-sphere (spheres smaller than its margin: its margin-free
// support is not its shape grown) dropped on a static box of ours rest on it at the height their lowest support
// point gives.
TEST_P(OtherShapes, ConvexShapesRestOnStaticBodyOfOurs) {
  std::vector<std::unique_ptr<btConvexShape>> falling;
  falling.push_back(std::make_unique<btCylinderShape>(btVector3(0.05f, 0.04f, 0.05f)));
  falling.push_back(std::make_unique<btConeShape>(btScalar(0.06), btScalar(0.08)));
  const btVector3 centres[2] = {btVector3(-0.03f, 0, 0), btVector3(0.03f, 0, 0)};
  const btScalar radii[2] = {0.03f, 0.03f};
  falling.push_back(std::make_unique<btMultiSphereShape>(centres, radii, 2));
  for (auto& shape : falling) {
    ShapesWorld w(GetParam());
    auto plate = BodyModel::buildFromMesh(makeBox(Vec3(0.3, 0.05, 0.3)), test::smallModelSettings(32, 2000, 1));
    w.add(std::make_unique<bullet::SdfccdShape>(plate), 0.0, Vec3::Zero());
    const double bottom = -double(shape->localGetSupportingVertex(btVector3(0, -1, 0)).y());
    const std::string name = shape->getName();
    btRigidBody& body =
        w.add(std::unique_ptr<btCollisionShape>(shape.release()), 1.0, Vec3(0, 0.05 + bottom + 0.03, 0));
    w.run(360);
    const double height = double(body.getWorldTransform().getOrigin().y());
    // A quarter of the plate's (coarse, 19 mm) cell: a shape grown by its margin twice would be 2 cm high.
    EXPECT_NEAR(height, 0.05 + bottom, 0.25 * plate->cellSize() + 0.002) << name;
    EXPECT_LT(bullet::toVec3(body.getLinearVelocity()).norm(), 0.05) << name;
    EXPECT_EQ(w.contacts->statistics().unsupportedPairs, 0) << name;
  }
}

// A 1 km ground of two triangles (a btBvhTriangleMeshShape) and a 1 km heightfield (513 x 513 samples of a
// 1-in-20 slope): our box rests on each at the analytic height; nothing is allocated per square metre.
TEST_P(OtherShapes, BoxRestsOnKilometreTriangleGround) {
  ShapesWorld w(GetParam());
  TriangleMesh ground;
  ground.vertices = {Vec3(-500, 0, -500), Vec3(500, 0, -500), Vec3(500, 0, 500), Vec3(-500, 0, 500)};
  ground.triangles = {{0, 2, 1}, {0, 3, 2}};
  w.addStaticMesh(ground);
  expectBoxRestsOn(w, 0.0, "1 km triangle ground");
}

// A btBvhTriangleMeshShape ground with a 4 cm margin (its field sits the margin above the triangles): our box
// set down at rest on the margin stays there. The triangles must be gathered as far as the margin reaches, or
// the box falls through the margin unseen and is kicked out of it.
TEST_P(OtherShapes, BoxSetOnMeshMarginStaysWithoutKick) {
  ShapesWorld w(GetParam());
  TriangleMesh ground;
  ground.vertices = {Vec3(-2, 0, -2), Vec3(2, 0, -2), Vec3(2, 0, 2), Vec3(-2, 0, 2)};
  ground.triangles = {{0, 2, 1}, {0, 3, 2}};
  const double margin = 0.04;
  w.addStaticMesh(ground).getCollisionShape()->setMargin(btScalar(margin));
  const auto model = smallBox();
  btRigidBody& box = w.add(std::make_unique<bullet::SdfccdShape>(model), 1.0, Vec3(0.01, margin + 0.05 + 0.0005, -0.01));
  double lowest = 1e300;
  double fastest = 0.0;
  for (int step = 0; step < 240; ++step) {
    w.run(1);
    lowest = std::min(lowest, lowestShellPoint(box, *model));
    fastest = std::max(fastest, double(box.getLinearVelocity().length()));
  }
  const double cell = model->cellSize();
  // Falling the 3 cm margin unseen would reach 0.8 m/s; a 0.5 mm settle reaches 0.1 m/s.
  EXPECT_GT(lowest, margin - 0.5 * cell) << "cell " << cell;
  EXPECT_LT(fastest, 0.15);
  EXPECT_NEAR(lowestShellPoint(box, *model), margin, 0.5 * cell);
  EXPECT_TRUE(w.log.empty());
}

// A btGImpactMeshShape ground (its margin lifts the surface): the same triangles through GImpact's own tree.
TEST_P(OtherShapes, BoxRestsOnGImpactMesh) {
  ShapesWorld w(GetParam());
  w.meshes.push_back(std::make_unique<btTriangleMesh>());
  w.meshes.back()->addTriangle(btVector3(-2, 0, -2), btVector3(2, 0, 2), btVector3(2, 0, -2));
  w.meshes.back()->addTriangle(btVector3(-2, 0, -2), btVector3(-2, 0, 2), btVector3(2, 0, 2));
  auto gimpact = std::make_unique<btGImpactMeshShape>(w.meshes.back().get());
  gimpact->setMargin(btScalar(0.01));
  gimpact->updateBound();
  w.add(std::move(gimpact), 0.0, Vec3::Zero());
  expectBoxRestsOn(w, 0.01, "GImpact mesh");
}

TEST_P(OtherShapes, BoxRestsOnKilometreHeightfield) {
  ShapesWorld w(GetParam());
  const int n = 513;  // 1000 m / 512 = 1.95 m per sample
  w.heights.emplace_back(static_cast<std::size_t>(n * n), 0.0f);
  auto terrain = std::make_unique<btHeightfieldTerrainShape>(n, n, w.heights.back().data(), btScalar(1), btScalar(-1),
                                                             btScalar(1), 1, PHY_FLOAT, false);
  terrain->setLocalScaling(btVector3(btScalar(1000.0 / (n - 1)), 1, btScalar(1000.0 / (n - 1))));
  w.add(std::move(terrain), 0.0, Vec3::Zero());
  expectBoxRestsOn(w, 0.0, "1 km heightfield");
}

// 20 m/s head-on into a wall of two triangles of zero thickness, at 1/60 s steps (33 cm per step, more than
// three times the box): the box never reaches the far side.
TEST_P(OtherShapes, NoTunnellingThroughThinMeshWallAt20MetresPerSecond) {
  ShapesWorld w(GetParam());
  w.world.setGravity(btVector3(0, 0, 0));
  TriangleMesh wall;
  wall.vertices = {Vec3(0, -1, -1), Vec3(0, 1, -1), Vec3(0, 1, 1), Vec3(0, -1, 1)};
  wall.triangles = {{0, 1, 2}, {0, 2, 3}};
  w.addStaticMesh(wall);
  const auto model = smallBox();
  btRigidBody& box = w.add(std::make_unique<bullet::SdfccdShape>(model), 1.0, Vec3(-0.5, 0.0, 0.0));
  box.setLinearVelocity(btVector3(20, 0, 0));
  double farthest = -1e9;
  for (int i = 0; i < 60; ++i) {
    w.run(1, 1.0 / 60.0);
    farthest = std::max(farthest, double(box.getWorldTransform().getOrigin().x()) + 0.05);
  }
  EXPECT_LE(farthest, 0.002) << "the box's front face passed the wall";
  EXPECT_LE(box.getLinearVelocity().x(), 0.5);
}

// A sharp mesh feature: a steep static pyramid (apex 10 cm above a 10 cm base) under our box. Its apex is a mesh
// vertex, which meets our field as a point (the mesh's other role): it never gets deeper into the box than a cell
// and the solver's margin, although it would fit between the box's shell points (about 1 cm apart).
TEST_P(OtherShapes, MeshApexMeetsOurFieldAsAPoint) {
  ShapesWorld w(GetParam());
  TriangleMesh pyramid;
  pyramid.vertices = {Vec3(0, 0.1, 0), Vec3(-0.05, 0, -0.05), Vec3(0.05, 0, -0.05), Vec3(0.05, 0, 0.05),
                      Vec3(-0.05, 0, 0.05)};
  pyramid.triangles = {{0, 2, 1}, {0, 3, 2}, {0, 4, 3}, {0, 1, 4}};
  w.addStaticMesh(pyramid);
  const auto model = smallBox();
  btRigidBody& box = w.add(std::make_unique<bullet::SdfccdShape>(model), 1.0, Vec3(0.0, 0.1 + 0.05 + 0.02, 0.0));
  double deepest = 0.0;  // of the apex in the box's field (m)
  for (int i = 0; i < 240; ++i) {
    w.run(1);
    const btVector3 apex = box.getWorldTransform().inverse()(btVector3(0, btScalar(0.1), 0));
    const Vec3 inField = model->bodyFromField().inverse() * bullet::toVec3(apex);
    deepest = std::min(deepest, model->field().distance(inField));
  }
  EXPECT_GT(deepest, -(model->cellSize() + 0.002)) << "cell " << model->cellSize();
  EXPECT_EQ(w.contacts->statistics().unsupportedPairs, 0);
}

// Compounds: a static compound of a cylinder and a box (our box lands on the cylinder child), and our box as a
// compound child dropped on a triangle mesh ground.
TEST_P(OtherShapes, CompoundsOfOtherShapesAndOfOurs) {
  {
    ShapesWorld w(GetParam());
    auto compound = std::make_unique<btCompoundShape>();
    btTransform at;
    at.setIdentity();
    at.setOrigin(btVector3(0, btScalar(0.1), 0));
    w.shapes.push_back(std::make_unique<btCylinderShape>(btVector3(0.3f, 0.05f, 0.3f)));
    compound->addChildShape(at, w.shapes.back().get());
    at.setOrigin(btVector3(2, 0, 0));
    w.shapes.push_back(std::make_unique<btBoxShape>(btVector3(0.3f, 0.3f, 0.3f)));
    compound->addChildShape(at, w.shapes.back().get());
    w.add(std::move(compound), 0.0, Vec3::Zero());
    expectBoxRestsOn(w, 0.15, "compound's cylinder child");
  }
  {
    ShapesWorld w(GetParam());
    TriangleMesh ground;
    ground.vertices = {Vec3(-5, 0, -5), Vec3(5, 0, -5), Vec3(5, 0, 5), Vec3(-5, 0, 5)};
    ground.triangles = {{0, 2, 1}, {0, 3, 2}};
    w.addStaticMesh(ground);
    const auto model = smallBox();
    auto compound = std::make_unique<btCompoundShape>();
    btTransform at;
    at.setIdentity();
    at.setOrigin(btVector3(0, btScalar(0.02), 0));
    w.shapes.push_back(std::make_unique<bullet::SdfccdShape>(model));
    compound->addChildShape(at, w.shapes.back().get());
    btRigidBody& body = w.add(std::move(compound), 1.0, Vec3(0, 0.1, 0));
    w.run(360);
    const double lowest = double(body.getWorldTransform().getOrigin().y()) + 0.02 - 0.05;
    EXPECT_NEAR(lowest, 0.0, model->cellSize() + 0.002);
    EXPECT_LT(bullet::toVec3(body.getLinearVelocity()).norm(), 0.05);
  }
}

INSTANTIATE_TEST_SUITE_P(BothModes, OtherShapes,
                         ::testing::Values(SdfccdContactMode::Solver, SdfccdContactMode::Penalty),
                         [](const auto& param) {
                           return std::string(param.param == SdfccdContactMode::Solver ? "Solver" : "Penalty");
                         });

/// A user's concave shape we know nothing about (a type id no Bullet shape of ours uses).
std::unique_ptr<btCollisionShape> userConcaveShape() {
  return std::make_unique<test::UserConcaveShape>(FAST_CONCAVE_MESH_PROXYTYPE, "UserConcaveShape");
}

// The pair is announced once per type pair (two such shapes, many steps) and every call is counted.
TEST(OtherShapesUnsupported, AnnouncedOnceAndCounted) {
  ShapesWorld w(SdfccdContactMode::Solver);
  w.add(userConcaveShape(), 0.0, Vec3(0, 0, 0));
  w.add(userConcaveShape(), 0.0, Vec3(0.5, 0, 0));
  w.add(std::make_unique<bullet::SdfccdShape>(smallBox()), 1.0, Vec3(0.2, 0.3, 0));
  w.run(10);
  ASSERT_EQ(w.log.size(), 1u);
  EXPECT_NE(w.log[0].find("UserConcaveShape"), std::string::npos) << w.log[0];
  EXPECT_NE(w.log[0].find("not supported"), std::string::npos) << w.log[0];
  EXPECT_GE(w.contacts->statistics().unsupportedPairs, 20);  // two pairs, ten steps
}

/// A 2 m x 2 m wavy terrain, 64 x 64 quads (8192 triangles) of height 0.03 sin(3x) cos(3z); `closed`: a slab
/// down to y = -0.1 (sides and bottom), for our SDF builder.
TriangleMesh wavyTerrain(bool closed) {
  const int n = 64;
  TriangleMesh mesh;
  auto height = [](double x, double z) { return 0.03 * std::sin(3 * x) * std::cos(3 * z); };
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const double x = -1 + 2.0 * i / n, z = -1 + 2.0 * j / n;
      mesh.vertices.emplace_back(x, height(x, z), z);
    }
  }
  auto at = [n](int i, int j) { return i * (n + 1) + j; };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      mesh.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  }
  if (!closed) return mesh;
  // The rim's vertices, counter-clockwise seen from above, each dropped to y = -0.1: side quads and a bottom fan.
  std::vector<int> rim;
  for (int j = 0; j < n; ++j) rim.push_back(at(0, j));
  for (int i = 0; i < n; ++i) rim.push_back(at(i, n));
  for (int j = n; j > 0; --j) rim.push_back(at(n, j));
  for (int i = n; i > 0; --i) rim.push_back(at(i, 0));
  const int base = static_cast<int>(mesh.vertices.size());
  for (int v : rim)
    mesh.vertices.emplace_back(mesh.vertices[static_cast<std::size_t>(v)].x(), -0.1,
                               mesh.vertices[static_cast<std::size_t>(v)].z());
  const int count = static_cast<int>(rim.size());
  for (int k = 0; k < count; ++k) {
    const int a = rim[static_cast<std::size_t>(k)], b = rim[static_cast<std::size_t>((k + 1) % count)];
    mesh.triangles.push_back({a, base + (k + 1) % count, b});
    mesh.triangles.push_back({a, base + k, base + (k + 1) % count});
  }
  mesh.vertices.emplace_back(0.0, -0.1, 0.0);
  for (int k = 0; k < count; ++k) {
    mesh.triangles.push_back({base + k, static_cast<int>(mesh.vertices.size()) - 1, base + (k + 1) % count});
  }
  return mesh;
}

// Measurement (docs/bullet.md, supported shape pairs): a bunny dropped on a static wavy level, its triangles exact (our
// shell against the triangles near it, btBvhTriangleMeshShape) and as a dense SDF of the closed level (a static body of
// ours). Prints the cost; checks the bunny comes to rest on the terrain either way. Run with
// --gtest_also_run_disabled_tests (slow: the level's SDF build).
TEST(OtherShapesMeasure, DISABLED_BunnyDropOnMeshLevelBothWays) {
  const auto bunny = test::buildTestBunny(1500);
  for (const bool exact : {true, false}) {
    ShapesWorld w(SdfccdContactMode::Solver);
    std::shared_ptr<const BodyModel> level;
    if (exact) {
      w.addStaticMesh(wavyTerrain(false));
    } else {
      BodyModelSettings ls;
      ls.resolution = 256;  // 7.8 mm cells over the 2 m level
      level = BodyModel::buildFromMesh(wavyTerrain(true), ls);
      btRigidBody& ground = w.add(std::make_unique<bullet::SdfccdShape>(level), 0.0, Vec3::Zero());
      // The body frame is the centre of mass and principal axes: placed so that the mesh frame is the world's.
      const Rigid& pose = level->modelFromBody();
      const Eigen::Matrix3d m = pose.linear();
      btTransform t(
          btMatrix3x3(btScalar(m(0, 0)), btScalar(m(0, 1)), btScalar(m(0, 2)), btScalar(m(1, 0)), btScalar(m(1, 1)),
                      btScalar(m(1, 2)), btScalar(m(2, 0)), btScalar(m(2, 1)), btScalar(m(2, 2))),
          btVector3(btScalar(pose.translation().x()), btScalar(pose.translation().y()),
                    btScalar(pose.translation().z())));
      ground.setWorldTransform(t);
    }
    const double lowest = -bunny->boundsInBody().min().y();
    btRigidBody& body = w.add(std::make_unique<bullet::SdfccdShape>(bunny), 1.0, Vec3(0.1, 0.03 + lowest + 0.05, 0.1));
    const auto start = std::chrono::steady_clock::now();
    w.run(480);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf(
        "%s: 480 steps %.3f s wall (%.3f ms/step), ccd %.3f s, level grid %s\n",
        exact ? "exact triangles" : "dense level SDF", wall, 1e3 * wall / 480, w.contacts->statistics().ccdSeconds,
        level ? (std::to_string(std::int64_t(level->field().grid().nodeCounts().prod()) * 4 / 1000000) + " MB").c_str()
              : "none");
    EXPECT_LT(bullet::toVec3(body.getLinearVelocity()).norm(), 0.05);
    EXPECT_GT(lowestShellPoint(body, *bunny), -0.035);  // above the terrain's lowest
    EXPECT_GT(w.contacts->lastStepContactCount(), 0);
  }
}

}  // namespace other_shapes_test
}  // namespace sdfccd
