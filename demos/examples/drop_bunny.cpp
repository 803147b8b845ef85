#include <btBulletDynamicsCommon.h>
#include <sdfccd/bullet/bullet_pose.h>
#include <sdfccd/bullet/contact_solver.h>
#include <sdfccd/bullet/contact_system.h>
#include <sdfccd/bullet/sdfccd_shape.h>

#include <cstdio>

int main() {
  namespace sb = sdfccd::bullet;
  sdfccd::BodyModelSettings settings;  // the model: distance field + point shell + mass properties, shareable
  settings.points = 777;               // shell points spread over the surface (0: the mesh's vertices)
  settings.scale = 0.2;
  const auto model = sdfccd::BodyModel::buildFromMeshFile("assets/meshes/bunny.off", settings);
  sb::SdfccdShape shape(model);
  btVector3 inertia;
  shape.calculateLocalInertia(1, inertia);
  btRigidBody bunny(1, nullptr, &shape, inertia);
  const btTransform meshPose(btQuaternion::getIdentity(), btVector3(0, 0.3f, 0));  // where the mesh should be
  bunny.setWorldTransform(sb::bodyTransformForMeshPose(*model, meshPose));
  btStaticPlaneShape plane(btVector3(0, 1, 0), 0);
  btRigidBody ground(0, nullptr, &plane);
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  auto solver = sb::makeContactSolver(sdfccd::ContactSolver::Mlcp);  // an exact solver for solver mode
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, solver.get(), &configuration);
  sb::configureContactSolver(world.getSolverInfo(), sdfccd::ContactSolver::Mlcp);
  world.setGravity(btVector3(0, -9.81f, 0));
  sb::ContactSystem contacts(world);  // sdfccd's contacts in this world, until `contacts` goes (before the world)
  world.addRigidBody(&ground);
  world.addRigidBody(&bunny);
  for (int i = 0; i < 480; ++i) world.stepSimulation(1.0f / 240, 0);
  std::printf("the bunny rests at y = %.3f m\n", bunny.getWorldTransform().getOrigin().y());
}
