/// @file
/// @brief Virtual coupling: linear below x_max, saturated at F_max = k x_max above; gradients against
/// finite differences; the device feels the reaction.
#include "sdfccd/haptics/virtual_coupling.h"

#include <gtest/gtest.h>

namespace sdfccd::haptics {
namespace {

RigidBodyState stateAt(const Vec3& p, const Vec3& rotationVec = Vec3::Zero()) {
  RigidBodyState s;
  s.worldFromBody.linear() = rotationFromVector(rotationVec);
  s.worldFromBody.translation() = p;
  return s;
}

TEST(VirtualCoupling, LinearBelowAndSaturatedAboveMaxDisplacement) {
  VirtualCouplingSettings vc;
  vc.linearStiffness = 1000.0;
  vc.maxDisplacement = 0.002;
  const CouplingWrench small = couplingWrench(stateAt(Vec3(0.001, 0, 0)), stateAt(Vec3::Zero()), vc);
  EXPECT_NEAR(small.onSimulation[0], 1.0, 1e-12);
  EXPECT_FALSE(small.linearSaturated);
  EXPECT_TRUE(small.onDevice.isApprox(-small.onSimulation));
  const CouplingWrench big = couplingWrench(stateAt(Vec3(0, 0.3, -0.4)), stateAt(Vec3::Zero()), vc);
  EXPECT_TRUE(big.linearSaturated);
  EXPECT_NEAR(big.onSimulation.head<3>().norm(), 1000.0 * 0.002, 1e-12);  // F_max = k x_max
  EXPECT_TRUE(big.onSimulation.head<3>().normalized().isApprox(Vec3(0, 0.6, -0.8)));
  const CouplingWrench turn = couplingWrench(stateAt(Vec3::Zero(), Vec3(0, 0, 1.0)), stateAt(Vec3::Zero()), vc);
  EXPECT_TRUE(turn.angularSaturated);
  EXPECT_NEAR(turn.onSimulation[5], vc.angularStiffness * vc.maxRotation, 1e-12);
}

TEST(VirtualCoupling, PoseGradientMatchesFiniteDifferences) {
  VirtualCouplingSettings vc;
  for (const Vec3& dp : {Vec3(3e-4, -2e-4, 1e-4), Vec3(0.01, 0.02, -0.005)}) {
    const RigidBodyState device = stateAt(dp, Vec3(0.01, -0.02, 0.015));
    const RigidBodyState sim = stateAt(Vec3::Zero(), Vec3(0.002, 0.0, -0.001));
    const CouplingWrench w = couplingWrench(device, sim, vc);
    const double h = 1e-7;
    for (int i = 0; i < 3; ++i) {  // translation columns (exact for the linear part)
      Vec6 e = Vec6::Zero();
      e[i] = h;
      RigidBodyState moved = sim;
      moved.worldFromBody = displacePose(sim.worldFromBody, e);
      const Vec6 fd = (couplingWrench(device, moved, vc).onSimulation - w.onSimulation) / h;
      EXPECT_LE((fd - w.poseGradient.col(i)).norm(), 1e-4 * (1.0 + w.poseGradient.col(i).norm()));
    }
  }
}

}  // namespace
}  // namespace sdfccd::haptics
