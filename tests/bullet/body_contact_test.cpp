// Per-body penalty parameters (ContactSystem::setBodyContact): a pair combines its bodies' values with the
// world's as documented (springs in series, normalised; means for damping), and a body without an override
// leaves the world's settings untouched.
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <memory>

#include "bullet_test_util.h"
#include "bullet_world_fixture.h"
#include "sdfccd/bullet/contact_system.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "sdfccd/error.h"
#include "sdfccd/mesh/procedural_meshes.h"

namespace sdfccd {
namespace body_contact_test {

std::shared_ptr<const BodyModel> ballModel() {
  static const std::shared_ptr<const BodyModel> model =
      BodyModel::buildFromMesh(makeIcosphere(0.1, 3), test::smallModelSettings(24, 300));
  return model;
}

bullet::ContactSettings perAreaPenalty(double stiffnessPerArea) {
  bullet::ContactSettings settings;
  settings.mode = SdfccdContactMode::Penalty;
  settings.penalty.stiffnessPerArea = stiffnessPerArea;
  return settings;
}

/// A 1 kg ball of radius 0.1 m dropped from 5 mm onto a static plane, in penalty mode with the per-area law.
class BallOnPlane {
 public:
  BallOnPlane(double worldStiffnessPerArea, const bullet::BodyContact* ballOverride)
      : world_(perAreaPenalty(worldStiffnessPerArea)) {
    world_.add(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), 0), 0.0, Vec3::Zero());
    ball_ = &world_.add(std::make_unique<bullet::SdfccdShape>(ballModel()), 1.0, Vec3(0, 0.105, 0));
    if (ballOverride != nullptr) contacts().setBodyContact(ball_, *ballOverride);
  }
  /// Steps 1 s at 1 kHz; returns the ball's height.
  double settle() {
    world_.step(1000, 0.001);
    return double(ball_->getWorldTransform().getOrigin().y());
  }
  bullet::ContactSystem& contacts() { return *world_.contacts; }
  const btRigidBody* ball() const { return ball_; }

 private:
  test::BulletTestWorld world_;
  btRigidBody* ball_ = nullptr;
};

// A ball with stiffness k0/4 against a plane at the world's k0 rests exactly as a ball in a world of
// 2 (k0/4) k0 / (k0/4 + k0) = 0.4 k0 without overrides, and deeper than at k0.
TEST(BodyContact, StiffnessCombinesLikeSpringsInSeries) {
  const double k0 = PenaltySettings::trustworthy().stiffnessPerArea;
  bullet::BodyContact soft;
  soft.stiffnessPerArea = 0.25 * k0;
  BallOnPlane overridden(k0, &soft);
  BallOnPlane equivalent(0.4 * k0, nullptr);
  BallOnPlane stiff(k0, nullptr);
  const double hOverridden = overridden.settle();
  const double hEquivalent = equivalent.settle();
  const double hStiff = stiff.settle();
  EXPECT_NEAR(hOverridden, hEquivalent, 1e-6);
  EXPECT_LT(hOverridden, hStiff - 1e-5);  // softer: deeper
  EXPECT_NEAR(hStiff, 0.1, 0.005);        // resting on the plane
}

// Overrides equal to the world's change nothing; clearing one restores the world's settings.
TEST(BodyContact, EqualOverrideAndClear) {
  const double k0 = PenaltySettings::trustworthy().stiffnessPerArea;
  bullet::BodyContact same;
  same.stiffnessPerArea = k0;
  BallOnPlane withSame(k0, &same);
  BallOnPlane plain(k0, nullptr);
  EXPECT_EQ(withSame.settle(), plain.settle());
  ASSERT_NE(withSame.contacts().bodyContact(withSame.ball()), nullptr);
  withSame.contacts().clearBodyContact(withSame.ball());
  EXPECT_EQ(withSame.contacts().bodyContact(withSame.ball()), nullptr);
}

TEST(BodyContact, BadValuesAreRefused) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  bullet::ContactSystem system(dispatcher);
  btCollisionObject body;
  bullet::BodyContact bad;
  bad.stiffness = -1.0;
  EXPECT_THROW(system.setBodyContact(&body, bad), Error);
  bad = {};
  bad.dampingRatio = 3.0;
  EXPECT_THROW(system.setBodyContact(&body, bad), Error);
  EXPECT_THROW(system.setBodyContact(nullptr, {}), Error);
  EXPECT_NO_THROW(system.setBodyContact(&body, {}));
}

// An override of another law than the world's is refused (its units differ, or the pair's law would ignore it).
TEST(BodyContact, OverridesOfAnotherLawAreRefused) {
  btCollisionObject body;
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  auto refused = [&](const bullet::ContactSettings& settings, const bullet::BodyContact& contact) {
    bullet::ContactSystem system(dispatcher, settings);
    try {
      system.setBodyContact(&body, contact);
    } catch (const Error&) {
      return true;
    }
    return false;
  };
  bullet::BodyContact perPoint, perArea, damping, ratio;
  perPoint.stiffness = 1000.0;
  perArea.stiffnessPerArea = 1.0e6;
  damping.damping = 1.0;
  ratio.dampingRatio = 0.5;
  const bullet::ContactSettings defaults;  // per-area stiffness, ratio from restitution
  EXPECT_TRUE(refused(defaults, perPoint));
  EXPECT_FALSE(refused(defaults, perArea));
  EXPECT_TRUE(refused(defaults, damping));
  EXPECT_TRUE(refused(defaults, ratio));
  bullet::ContactSettings paper;  // the paper's law: per point, per-point damping
  paper.penalty = PenaltySettings{};
  EXPECT_FALSE(refused(paper, perPoint));
  EXPECT_TRUE(refused(paper, perArea));
  EXPECT_FALSE(refused(paper, damping));
  EXPECT_TRUE(refused(paper, ratio));
  bullet::ContactSettings explicitRatio = defaults;
  explicitRatio.penalty.dampingRatioFromRestitution = false;
  EXPECT_FALSE(refused(explicitRatio, ratio));
  EXPECT_TRUE(refused(explicitRatio, damping));
  bullet::BodyContact zeroArea;
  zeroArea.stiffnessPerArea = 0.0;
  EXPECT_TRUE(refused(defaults, zeroArea));
}

}  // namespace body_contact_test
}  // namespace sdfccd
