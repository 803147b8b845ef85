// hello_world: Bullet's HelloWorld with sdfccd bodies. A ground plane, a static triangle-mesh ramp, a box, a
// cylinder and four bunnies (SdfccdShape: a point shell and a distance field each) fall for two seconds; the
// program prints which bodies touched which, and when they first did, each body's final height, and whether the
// bunnies placed on the cylinder and on the ramp fell through them (they do not; both tip off and land beside).
//
// Build against the installed package (see CMakeLists.txt beside this file):
//   cmake -S demos/examples -B build-examples -DCMAKE_PREFIX_PATH=<install prefix> && cmake --build build-examples
//   ./build-examples/hello_world [path/to/bunny.off]
#include <btBulletDynamicsCommon.h>
#include <sdfccd/bullet/bullet_pose.h>
#include <sdfccd/bullet/contact_solver.h>
#include <sdfccd/bullet/contact_system.h>
#include <sdfccd/bullet/sdfccd_shape.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

int main(int argc, char** argv) {
  const std::string meshPath = argc > 1 ? argv[1] : "assets/meshes/bunny.off";

  // The world, as in Bullet's HelloWorld; then the contact system installs sdfccd's collision algorithms and its
  // response in it until it goes (btDiscreteDynamicsWorldMt is refused).
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  // Solver mode (the default) hands the contacts to Bullet's constraint solver: the exact MLCP one keeps stacks
  // and heavy-on-light pairs from creeping (sdfccd/bullet/contact_solver.h).
  auto solver = sdfccd::bullet::makeContactSolver(sdfccd::ContactSolver::Mlcp);
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, solver.get(), &configuration);
  sdfccd::bullet::configureContactSolver(world.getSolverInfo(), sdfccd::ContactSolver::Mlcp);
  world.setGravity(btVector3(0, -9.81f, 0));
  sdfccd::bullet::ContactSystem contacts(world);

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
    add(name, new sdfccd::bullet::SdfccdShape(bunny), 0.2f,
        sdfccd::bullet::bodyTransformForMeshPose(*bunny, at(where.x(), where.y(), where.z())));
  };
  addBunny("bunny-1", btVector3(0, 0.6f * height, 0));
  addBunny("bunny-2", btVector3(0.005f, 2.2f * height, 0.003f));              // lands on bunny-1
  addBunny("bunny-on-cylinder", btVector3(-0.3f, 0.05f + 1.5f * height, 0));  // needs bunny-cylinder contact
  addBunny("bunny-on-ramp", btVector3(0.4f, 0.1f + 1.5f * height, 0));        // needs bunny-triangle-mesh contact

  // Two seconds at 240 Hz; after each step, every manifold with a touching point is a contact. Solver mode also
  // writes speculative points at a positive distance (a gap that may close within the step), which are not
  // touches. The resting points here measure 0 to 0.6 mm (the solver settles them at zero or a hair above), so
  // 1 mm (under a third of the bunny field's 3.7 mm cell) counts them and leaves out a falling body's gap.
  const btScalar touchTolerance = 0.001f;
  auto touches = [&](const btPersistentManifold* manifold) {
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      if (manifold->getContactPoint(p).getDistance() <= touchTolerance) return true;
    }
    return false;
  };
  // Did a bunny pass through what it was placed on? (It may tip off a support and land beside it: the scene is
  // not balanced, and that is mechanics, not a failure.) After each step, the cylinder's check is the deepest any
  // bunny shell point gets inside the solid cylinder, which must stay under one cell of the bunny's field (the
  // penetration the contact allows); the ramp is a sheet of two triangles with no inside, so its check is that the
  // bunny's centre never crosses from above the sheet to below it within the sheet's 20 cm square.
  const btScalar cell = height / btScalar(settings.resolution);
  auto bodyNamed = [&](const std::string& name) -> const btRigidBody& {
    for (const auto& body : bodies) {
      if (names[body.get()] == name) return *body;
    }
    std::fprintf(stderr, "hello_world: no body named %s\n", name.c_str());
    std::exit(2);
  };
  const btRigidBody& cylinder = bodyNamed("cylinder");
  const btRigidBody& onCylinder = bodyNamed("bunny-on-cylinder");
  const btTransform rampPose = bodyNamed("ramp").getWorldTransform();  // static
  const btRigidBody& onRamp = bodyNamed("bunny-on-ramp");
  btScalar deepestInCylinder = 0;
  bool crossedRamp = false;
  btScalar rampSide = 1;  // the bunny's centre above the ramp's sheet (> 0) or below it; it starts above
  auto watchSupports = [&] {
    const btTransform cylinderFromBunny = cylinder.getWorldTransform().inverse() * onCylinder.getWorldTransform();
    for (const sdfccd::Vec3& q : bunny->shell().positions) {
      const btVector3 l = cylinderFromBunny * sdfccd::bullet::toBtVector3(q);
      const btScalar depth = btMin(0.03f - btSqrt(l.x() * l.x() + l.z() * l.z()), 0.02f - btFabs(l.y()));
      deepestInCylinder = btMax(deepestInCylinder, depth);
    }
    const btVector3 c = rampPose.inverse() * onRamp.getWorldTransform().getOrigin();
    if (rampSide > 0 && c.y() < 0 && btFabs(c.x()) < 0.1f && btFabs(c.z()) < 0.1f) crossedRamp = true;
    rampSide = c.y();
  };
  std::map<std::pair<std::string, std::string>, double> firstTouch;
  const btScalar dt = 1.0f / 240;
  for (int step = 1; step <= 480; ++step) {
    world.stepSimulation(dt, 0);
    watchSupports();
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
      const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
      if (!touches(manifold)) continue;
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
    std::printf("%-18s rests at (%.3f, %.3f, %.3f), final height %.4f m\n", names[body.get()].c_str(), p.x(), p.y(),
                p.z(), p.y());
  }

  const bool throughCylinder = deepestInCylinder >= cell;
  std::printf("bunny-on-cylinder %s cylinder (deepest shell point %.4f m inside it, cell %.4f m)\n",
              throughCylinder ? "FELL THROUGH" : "did not fall through", deepestInCylinder, cell);
  std::printf("bunny-on-ramp %s ramp\n", crossedRamp ? "FELL THROUGH" : "did not fall through");
  const bool fellThrough = throughCylinder || crossedRamp;
  for (auto& body : bodies) world.removeRigidBody(body.get());
  return firstTouch.empty() || fellThrough ? 1 : 0;
}
