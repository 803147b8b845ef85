// hello_world: Bullet's HelloWorld with sdfccd bodies. A ground plane, a static triangle-mesh ramp, a box, a
// cylinder and four bunnies (SdfccdShape: a point shell and a distance field each) fall for two seconds; the
// program prints which bodies touched which, and when they first did.
//
// Build against the installed package (see CMakeLists.txt beside this file):
//   cmake -S demos/examples -B build-examples -DCMAKE_PREFIX_PATH=<install prefix> && cmake --build build-examples
//   ./build-examples/hello_world [path/to/bunny.off]
#include <btBulletDynamicsCommon.h>
#include <sdfccd/bullet/bullet_pose.h>
#include <sdfccd/bullet/sdfccd_contact_system.h>
#include <sdfccd/bullet/sdfccd_shape.h>

#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

int main(int argc, char** argv) {
  const std::string meshPath = argc > 1 ? argv[1] : "assets/meshes/bunny.off";

  // The world, as in Bullet's HelloWorld; then one call installs sdfccd's collision algorithms (the
  // registration owns the contact system; btDiscreteDynamicsWorldMt is refused).
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, -9.81f, 0));
  sdfccd::registerSdfccdAlgorithms(&world);

  // Shapes and bodies are the program's (Bullet's rule: keep a shape alive while a body uses it).
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  std::map<const btCollisionObject*, std::string> names;
  auto add = [&](const std::string& name, btCollisionShape* shape, btScalar mass, const btTransform& pose) {
    shapes.emplace_back(shape);
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(mass, inertia);
    bodies.push_back(std::make_unique<btRigidBody>(mass, nullptr, shape, inertia));
    bodies.back()->setWorldTransform(pose);
    world.addRigidBody(bodies.back().get());
    names[bodies.back().get()] = name;
  };
  auto at = [](btScalar x, btScalar y, btScalar z) {
    return btTransform(btQuaternion::getIdentity(), btVector3(x, y, z));
  };

  add("ground", new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, at(0, 0, 0));
  // A static ramp: two triangles of a btBvhTriangleMeshShape, tilted 20 degrees.
  auto ramp = std::make_unique<btTriangleMesh>();
  ramp->addTriangle(btVector3(-0.1f, 0, -0.1f), btVector3(0.1f, 0, -0.1f), btVector3(0.1f, 0, 0.1f));
  ramp->addTriangle(btVector3(-0.1f, 0, -0.1f), btVector3(0.1f, 0, 0.1f), btVector3(-0.1f, 0, 0.1f));
  auto* rampShape = new btBvhTriangleMeshShape(ramp.get(), true);
  add("ramp", rampShape, 0, btTransform(btQuaternion(btVector3(0, 0, 1), 0.35f), btVector3(0.4f, 0.08f, 0)));
  add("box", new btBoxShape(btVector3(0.02f, 0.02f, 0.02f)), 0.3f, at(-0.15f, 0.1f, 0));
  add("cylinder", new btCylinderShape(btVector3(0.03f, 0.02f, 0.03f)), 0.3f, at(-0.3f, 0.05f, 0));

  // The bunny: one model (field, shell, mass properties), shared by every bunny body. Its body frame is the
  // centre of mass and principal axes: bodyTransformForMeshPose places the mesh as its file has it.
  sdfccd::BodyModelSettings settings;
  settings.resolution = 64;
  settings.points = 777;
  settings.scale = 0.2;
  const auto bunny = sdfccd::BodyModel::buildFromMeshFile(meshPath, settings);
  const btScalar height = btScalar(bunny->boundsInBody().sizes().maxCoeff());
  auto addBunny = [&](const std::string& name, const btVector3& where) {
    add(name, new sdfccd::SdfccdShape(bunny), 0.2f,
        sdfccd::bodyTransformForMeshPose(*bunny, at(where.x(), where.y(), where.z())));
  };
  addBunny("bunny-1", btVector3(0, 0.6f * height, 0));
  addBunny("bunny-2", btVector3(0.005f, 2.2f * height, 0.003f));              // lands on bunny-1
  addBunny("bunny-on-cylinder", btVector3(-0.3f, 0.05f + 1.5f * height, 0));  // needs bunny-cylinder contact
  addBunny("bunny-on-ramp", btVector3(0.4f, 0.1f + 1.5f * height, 0));        // needs bunny-triangle-mesh contact

  // Two seconds at 240 Hz; after each step, every manifold with a point is a contact.
  std::map<std::pair<std::string, std::string>, double> firstTouch;
  const btScalar dt = 1.0f / 240;
  for (int step = 1; step <= 480; ++step) {
    world.stepSimulation(dt, 0);
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
      const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
      if (manifold->getNumContacts() == 0) continue;
      std::string a = names[manifold->getBody0()], b = names[manifold->getBody1()];
      if (b < a) std::swap(a, b);
      firstTouch.emplace(std::make_pair(a, b), step * dt);
    }
  }
  for (const auto& [pair, time] : firstTouch) {
    std::printf("%s touched %s at t = %.3f s\n", pair.first.c_str(), pair.second.c_str(), time);
  }
  for (const auto& body : bodies) {
    const btVector3 p = body->getWorldTransform().getOrigin();
    std::printf("%-18s rests at (%.3f, %.3f, %.3f)\n", names[body.get()].c_str(), p.x(), p.y(), p.z());
  }
  for (auto& body : bodies) world.removeRigidBody(body.get());
  sdfccd::releaseSdfccdAlgorithms(&world);
  return firstTouch.empty() ? 1 : 0;
}
