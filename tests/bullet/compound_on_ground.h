// The two-child compound of the textbook suites: two SdfccdShape boxes in one btCompoundShape, 2 kg,
// above a btStaticPlaneShape ground, in a plain btDiscreteDynamicsWorld with the contact system registered.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <memory>

#include "sdfccd/bullet/contact_solver.h"
#include "sdfccd/bullet/contact_system.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "sdfccd/mesh/procedural_meshes.h"
#include "sdfccd/model/body_model.h"

namespace sdfccd::test {

class CompoundOnGround {
 public:
  /// Children: boxes of half extent `half` (32^3 fields) at the child frames `left` and `right`; the compound's
  /// centre starts at height `startHeight` above the ground y = 0.
  CompoundOnGround(const bullet::ContactSettings& settings, double half, const btTransform& left,
                   const btTransform& right, double startHeight, double gravity)
      : solver_(bullet::makeContactSolver(solverFor(settings))),
        model_(buildModel(half)),
        leftShape_(model_),
        rightShape_(model_) {
    bullet::configureContactSolver(world_.getSolverInfo(), solverFor(settings));
    world_.setGravity(btVector3(0, btScalar(-gravity), 0));
    contacts_ = std::make_unique<bullet::ContactSystem>(world_, settings);
    compound_.addChildShape(left, &leftShape_);
    compound_.addChildShape(right, &rightShape_);
    btVector3 inertia;
    compound_.calculateLocalInertia(2, inertia);
    btRigidBody::btRigidBodyConstructionInfo info(2, nullptr, &compound_, inertia);
    info.m_startWorldTransform.setIdentity();
    info.m_startWorldTransform.setOrigin(btVector3(0, btScalar(startHeight), 0));
    body_ = std::make_unique<btRigidBody>(info);
    world_.addRigidBody(&ground_);
    world_.addRigidBody(body_.get());
  }
  ~CompoundOnGround() {
    world_.removeRigidBody(body_.get());
    world_.removeRigidBody(&ground_);
    contacts_.reset();
  }

  void step(int steps, double dt) {
    for (int i = 0; i < steps; ++i) world_.stepSimulation(btScalar(dt), 0);
  }
  btRigidBody& body() { return *body_; }
  double cellSize() const { return model_->cellSize(); }

  /// The lowest shell point of child `index` in world height, m.
  double lowestShellPoint(int index) const {
    const btTransform frame = body_->getWorldTransform() * compound_.getChildTransform(index);
    double lowest = 1e9;
    for (const Vec3& p : model_->shell().positions) {
      lowest = std::min(lowest, double((frame * btVector3(btScalar(p.x()), btScalar(p.y()), btScalar(p.z()))).y()));
    }
    return lowest;
  }

 private:
  static ContactSolver solverFor(const bullet::ContactSettings& settings) {
    return settings.mode == SdfccdContactMode::Solver ? ContactSolver::Mlcp : ContactSolver::SequentialImpulse;
  }
  static std::shared_ptr<const BodyModel> buildModel(double half) {
    BodyModelSettings ms;
    ms.resolution = 32;
    ms.boxHalfExtents = Vec3::Constant(half);
    return BodyModel::buildFromMesh(makeBox(Vec3::Constant(half)), ms);
  }

  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_{&configuration_};
  btDbvtBroadphase broadphase_;
  // Solver mode gets the solver a Bullet user should build (contact_solver.h); penalty mode Bullet's default.
  std::unique_ptr<btConstraintSolver> solver_;
  btDiscreteDynamicsWorld world_{&dispatcher_, &broadphase_, solver_.get(), &configuration_};
  std::shared_ptr<const BodyModel> model_;
  bullet::SdfccdShape leftShape_, rightShape_;
  btCompoundShape compound_;
  btStaticPlaneShape plane_{btVector3(0, 1, 0), 0};
  btRigidBody ground_{btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &plane_)};
  std::unique_ptr<bullet::ContactSystem> contacts_;
  std::unique_ptr<btRigidBody> body_;
};

}  // namespace sdfccd::test
