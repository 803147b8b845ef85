// A downstream program built against the *installed* package (find_package(sdfccd)), linking every exported
// target: core (a field), io (a mesh file), model (a scene), haptics (a virtual coupling) and bullet (a world
// with a bunny, a box and a ground plane: the bunny must come to rest on the ground).
#include <btBulletDynamicsCommon.h>
#include <sdfccd/bullet/bullet_pose.h>
#include <sdfccd/bullet/contact_solver.h>
#include <sdfccd/bullet/contact_system.h>
#include <sdfccd/bullet/sdfccd_shape.h>
#include <sdfccd/field/sdf_grid.h>
#include <sdfccd/haptics/virtual_coupling.h>
#include <sdfccd/io/mesh_loader.h>
#include <sdfccd/model/scene.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace {

int fail(const char* what) {
  std::printf("consumer: %s\n", what);
  return 1;
}

/// The bunny dropped from 5 cm beside a box, on a ground plane; true when it rests on the ground.
bool bunnyRestsOnTheGround(const std::string& meshPath) {
  sdfccd::BodyModelSettings settings;
  settings.resolution = 48;
  settings.points = 777;
  settings.scale = 0.2;
  const auto model = sdfccd::BodyModel::buildFromMeshFile(meshPath, settings);
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  // Solver mode (the default) hands the contacts to Bullet's constraint solver: the exact MLCP one keeps stacks
  // and heavy-on-light pairs from creeping (sdfccd/bullet/contact_solver.h).
  auto solver = sdfccd::bullet::makeContactSolver(sdfccd::ContactSolver::Mlcp);
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, solver.get(), &configuration);
  sdfccd::bullet::configureContactSolver(world.getSolverInfo(), sdfccd::ContactSolver::Mlcp);
  world.setGravity(btVector3(0, -9.81f, 0));
  sdfccd::bullet::ContactSystem contacts(world);  // removed from the world when it goes, before the world
  btStaticPlaneShape groundShape(btVector3(0, 1, 0), 0);
  btRigidBody ground(0, nullptr, &groundShape);
  world.addRigidBody(&ground);
  btBoxShape boxShape(btVector3(0.02f, 0.02f, 0.02f));
  btVector3 boxInertia;
  boxShape.calculateLocalInertia(0.5f, boxInertia);
  btRigidBody box(0.5f, nullptr, &boxShape, boxInertia);
  box.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.1f, 0.02f, 0)));
  world.addRigidBody(&box);
  sdfccd::bullet::SdfccdShape bunnyShape(model);
  btVector3 inertia;
  bunnyShape.calculateLocalInertia(1.0f, inertia);
  btRigidBody bunny(1.0f, nullptr, &bunnyShape, inertia);
  const double lowest = -model->boundsInBody().min().y();
  bunny.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, btScalar(lowest + 0.05), 0)));
  world.addRigidBody(&bunny);
  for (int i = 0; i < 480; ++i) world.stepSimulation(1.0f / 240, 0);
  // At rest: slow, and its lowest mesh vertex within a few millimetres of the ground.
  const btTransform pose = bunny.getWorldTransform();
  double minY = 1e9;
  for (const sdfccd::Vec3& v : model->meshInBody().vertices) {
    minY = std::min(minY, double(pose(sdfccd::bullet::toBtVector3(v)).y()));
  }
  std::printf("consumer: bunny lowest point %.4f m, speed %.4f m/s\n", minY, bunny.getLinearVelocity().length());
  const bool rests = std::abs(minY) < 0.003 && bunny.getLinearVelocity().length() < 0.05;
  world.removeRigidBody(&bunny);
  world.removeRigidBody(&box);
  world.removeRigidBody(&ground);
  return rests;
}

}  // namespace

int main() {
  // core: a 2x2x2-node field phi(x,y,z) = x + 2y + 3z - 1, trilinear at one point.
  std::vector<float> values;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) values.push_back(static_cast<float>(i + 2 * j + 3 * k - 1));
  sdfccd::SdfGrid grid({2, 2, 2}, sdfccd::Vec3::Zero(), 1.0, std::move(values));
  const double expected = 0.25 + 1.0 + 2.25 - 1.0;
  if (std::abs(grid.interpolate(sdfccd::Vec3(0.25, 0.5, 0.75)) - expected) > 1e-12) return fail("core: bad value");
  // model: a one-body scene.
  const sdfccd::Scene scene = sdfccd::parseScene(
      R"({"bodies": [{"primitive": {"type": "sphere", "radius": 0.1}, "mass": 2.0}]})", "consumer", ".");
  if (scene.bodies.size() != 1 || scene.bodies[0].mass != 2.0) return fail("model: the scene was not read");
  // io: the bunny's mesh file.
  const std::string meshPath = std::string(SDFCCD_ASSETS_DIR) + "/meshes/bunny.off";
  if (sdfccd::loadMesh(meshPath).triangles.size() < 1000) return fail("io: the bunny was not read");
  // haptics: a device 1 mm from the simulated object pulls it with k x.
  sdfccd::haptics::RigidBodyState device, simulated;
  device.worldFromBody.translation() = sdfccd::Vec3(0.0005, 0, 0);
  const auto wrench = sdfccd::haptics::couplingWrench(device, simulated, {});
  if (!(wrench.onSimulation[0] > 0)) return fail("haptics: no coupling force");
  // bullet: the bunny rests on the ground.
  if (!bunnyRestsOnTheGround(meshPath)) return fail("bullet: the bunny does not rest on the ground");
  std::printf("consumer: ok\n");
  return 0;
}
