/// @file
/// @brief The virtual coupling integrated implicitly with the object (implicit_coupling.h) against analytic
/// backward Euler answers, and the penalty renderer's coherent CCD against the fresh query.
#include <gtest/gtest.h>

#include <cmath>

#include "haptics/haptic_test_scenes.h"
#include "sdfccd/error.h"
#include "sdfccd/haptics/device_emulator.h"
#include "sdfccd/haptics/haptic_scene.h"
#include "sdfccd/haptics/penalty_renderer.h"

namespace sdfccd::haptics {
namespace {

/// The plane scene's box, 1 m above the plane (no contact), joined to the device by a linear, undamped coupling
/// spring of stiffness k (no saturation).
struct FreeBox {
  HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  PenaltyRendererSettings settings;
  Rigid start = Rigid::Identity();

  FreeBox(double k, CouplingIntegration integration) {
    settings = scene.penalty;
    settings.timestep = 1e-3;
    settings.coupling.linearStiffness = k;
    settings.coupling.linearDamping = 0.0;
    settings.coupling.angularDamping = 0.0;
    settings.coupling.maxDisplacement = 1e9;
    settings.couplingIntegration = integration;
    settings.deviceModel = {0.3, Vec3::Constant(4e-4), 0.0, 0.0};
    start.translation() = Vec3(0.0, 1.0, 0.0);
  }
  PenaltyRenderer renderer() const {
    return PenaltyRenderer(ObstacleContacts(*scene.tree, *scene.plane, Rigid::Identity()), start, settings);
  }
};

// The object's side (the paper's admittance mode): against a device moving at constant speed u, the object follows
// x' = x + h v', v' = v + h k/m (xh' - x') with xh' = xh + h u, and the device is rendered -k (xh' - x') (the
// spring at the end of the step). Written out in one dimension here, independently of the 6-DoF code.
TEST(ImplicitCoupling, ObjectSideIsBackwardEulerAgainstAMovingDevice) {
  const double k = 800.0, h = 1e-3, u = 0.05;
  FreeBox box(k, CouplingIntegration::Implicit);
  PenaltyRenderer r = box.renderer();
  const double m = box.settings.mass;
  RigidBodyState device;
  device.worldFromBody = box.start;
  device.worldFromBody.translation().x() = 0.004;  // 4 mm ahead of the object
  device.linearVelocity = Vec3(u, 0.0, 0.0);
  double x = 0.0, v = 0.0, xh = 0.004;
  double worst = 0.0, worstForce = 0.0;
  for (int n = 0; n < 300; ++n) {
    const PenaltyStepResult step = r.step(device);
    const double xhNext = xh + h * u;
    v = (v + h * k / m * (xhNext - x)) / (1.0 + h * h * k / m);
    x += h * v;
    worst = std::max(worst, std::abs(r.state().worldFromBody.translation().x() - x));
    worstForce = std::max(worstForce, std::abs(step.wrenchOnDevice.x() + k * (xhNext - x)));
    EXPECT_LT(step.wrenchOnDevice.tail<3>().norm(), 1e-12);
    xh = xhNext;
    device.worldFromBody.translation().x() = xh;
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worstForce, 1e-9);
  EXPECT_GT(std::abs(x), 1e-3);  // it moved: the comparison is not between two rests
}

/// A box and the emulated device (no hand, no friction) joined by the coupling; per tick, the momentum and the
/// energy of the relative motion (reduced mass mu).
struct TwoBodyRun {
  double maxMomentum = 0.0;      ///< |m_s v_s + m_h v_h| (starts at 0)
  double worstRatioError = 0.0;  ///< |E'/E - 1/(1 + h^2 k/mu)| per tick
  double maxEnergyGrowth = 0.0;  ///< max E_n / E_0
  double worstPrediction = 0.0;  ///< the device's pose vs the renderer's prediction (ImplicitWithDevice)
};

TwoBodyRun runTwoBodies(double k, CouplingIntegration integration, int ticks) {
  FreeBox box(k, integration);
  PenaltyRenderer r = box.renderer();
  DeviceSettings ds;
  ds.mass = box.settings.deviceModel.mass;
  ds.inertiaDiagonal = box.settings.deviceModel.inertiaDiagonal;
  ds.linearFriction = ds.angularFriction = 0.0;
  ds.userStiffness = ds.userDamping = ds.userAngularStiffness = ds.userAngularDamping = 0.0;
  ds.maxForce = ds.maxTorque = 1e12;
  Rigid deviceStart = box.start;
  deviceStart.translation().x() = 0.002;  // the spring stretched 2 mm
  DeviceEmulator device(ds, UserScript({{0.0, deviceStart}}), deviceStart);
  const double ms = box.settings.mass, mh = ds.mass, h = box.settings.timestep;
  const double mu = ms * mh / (ms + mh);
  const auto relativeEnergy = [&] {
    const double w = r.state().linearVelocity.x() - device.state().body.linearVelocity.x();
    const double d = r.state().worldFromBody.translation().x() - device.state().body.worldFromBody.translation().x();
    return 0.5 * mu * w * w + 0.5 * k * d * d;
  };
  TwoBodyRun run;
  const double e0 = relativeEnergy();
  double e = e0;
  for (int n = 0; n < ticks; ++n) {
    const PenaltyStepResult step = r.step(device.state().body);
    device.step(step.wrenchOnDevice);
    const double eNext = relativeEnergy();
    // The ratio while the energy is well above rounding (the stiff spring's decays by 28x per tick).
    if (e > 1e-8 * e0)
      run.worstRatioError = std::max(run.worstRatioError, std::abs(eNext / e - 1.0 / (1.0 + h * h * k / mu)));
    run.maxEnergyGrowth = std::max(run.maxEnergyGrowth, eNext / e0);
    run.maxMomentum = std::max(
        run.maxMomentum, std::abs(ms * r.state().linearVelocity.x() + mh * device.state().body.linearVelocity.x()));
    e = eNext;
    if (!std::isfinite(e)) break;
  }
  return run;
}

// With the device's model in the step, the coupled pair is the backward Euler step of two masses and a spring: the
// emulated device lands where the step predicted, momentum stays zero and the relative energy shrinks by exactly
// 1 / (1 + h^2 k / mu) per tick (the amplification of backward Euler on x'' = -(k/mu) x).
TEST(ImplicitCoupling, WithTheDeviceModelTheEmulatorAndObjectAreTwoBodyBackwardEuler) {
  for (const double k : {800.0, 2e6}) {
    const TwoBodyRun run = runTwoBodies(k, CouplingIntegration::ImplicitWithDevice, 400);
    EXPECT_LT(run.worstRatioError, 1e-9) << "k " << k;
    EXPECT_LT(run.maxMomentum, 1e-12) << "k " << k;
    EXPECT_LE(run.maxEnergyGrowth, 1.0) << "k " << k;
  }
}

// The same stiff spring (k h^2 / m_h = 6.7 > 4) with the device frozen in the object's step and integrated explicitly
// by the emulator (CouplingIntegration::Explicit) gains energy without bound: what the device's model in the step
// removes.
TEST(ImplicitCoupling, StiffCouplingExplicitOnTheDeviceSideGainsEnergy) {
  EXPECT_GT(runTwoBodies(2e6, CouplingIntegration::Explicit, 60).maxEnergyGrowth, 1e3);
  EXPECT_LE(runTwoBodies(2e6, CouplingIntegration::ImplicitWithDevice, 60).maxEnergyGrowth, 1.0);
}

TEST(ImplicitCoupling, BadSettingsAreRefused) {
  FreeBox box(800.0, CouplingIntegration::ImplicitWithDevice);
  box.settings.deviceModel.mass = 0.0;
  EXPECT_THROW(box.renderer(), Error);
  box.settings.couplingIntegration = CouplingIntegration::Implicit;
  box.settings.implicit = false;
  EXPECT_THROW(box.renderer(), Error);
  EXPECT_EQ(parseCouplingIntegration("implicit-device"), CouplingIntegration::ImplicitWithDevice);
  EXPECT_THROW(parseCouplingIntegration("semi"), Error);
}

// The penalty renderer's CCD from the last tick's front (temporal coherence) gives the fresh query's contacts, so the
// whole scripted insertion of the peg is bit for bit the same; and the coherence did skip nodes.
TEST(PenaltyRendererCoherence, PegInsertionIsBitIdenticalToTheFreshQuery) {
  const HapticScene scene = loadHapticScene(test::scenePath("peg-in-hole.json"));
  ASSERT_TRUE(scene.grid);
  const auto makeSettings = [&](bool coherent) {
    PenaltyRendererSettings s = scene.penalty;
    s.contact.model = PenaltyModel::Continuous;
    s.timestep = 1.0 / scene.device.rateHz;
    s.coherentCcd = coherent;
    return s;
  };
  PenaltyRenderer fresh(ObstacleContacts(*scene.tree, *scene.grid, scene.worldFromSdf), scene.worldFromBodyStart,
                        makeSettings(false));
  PenaltyRenderer coherent(ObstacleContacts(*scene.tree, *scene.grid, scene.worldFromSdf), scene.worldFromBodyStart,
                           makeSettings(true));
  DeviceEmulator deviceA(scene.device, scene.script, scene.worldFromBodyStart);
  DeviceEmulator deviceB(scene.device, scene.script, scene.worldFromBodyStart);
  const int ticks = static_cast<int>(scene.seconds * scene.device.rateHz);
  std::int64_t certified = 0, freshCertified = 0;
  int contactTicks = 0, mismatches = 0;
  for (int n = 0; n < ticks; ++n) {
    const PenaltyStepResult a = fresh.step(deviceA.state().body);
    const PenaltyStepResult b = coherent.step(deviceB.state().body);
    freshCertified += a.certifiedNodes;
    certified += b.certifiedNodes;
    contactTicks += a.contactCount > 0;
    mismatches += !(a.contactWrench == b.contactWrench) || a.contactCount != b.contactCount ||
                  !(fresh.state().worldFromBody.matrix() == coherent.state().worldFromBody.matrix()) ||
                  !(a.wrenchOnDevice == b.wrenchOnDevice);
    deviceA.step(a.wrenchOnDevice);
    deviceB.step(b.wrenchOnDevice);
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(contactTicks, 500);  // the peg was in contact for a good part of the run
  EXPECT_EQ(freshCertified, 0);
  EXPECT_GT(certified, 0);
}

}  // namespace
}  // namespace sdfccd::haptics
