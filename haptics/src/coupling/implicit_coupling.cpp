/// @file
/// @brief The coupled backward Euler step of the virtual coupling (see implicit_coupling.h).
#include "sdfccd/haptics/implicit_coupling.h"

#include <Eigen/LU>
#include <cmath>

#include "sdfccd/error.h"

namespace sdfccd::haptics {

const char* toString(CouplingIntegration integration) {
  switch (integration) {
    case CouplingIntegration::Explicit:
      return "explicit";
    case CouplingIntegration::Implicit:
      return "implicit";
    case CouplingIntegration::ImplicitWithDevice:
      return "implicit-device";
  }
  return "?";
}

CouplingIntegration parseCouplingIntegration(const std::string& name) {
  for (CouplingIntegration c :
       {CouplingIntegration::Explicit, CouplingIntegration::Implicit, CouplingIntegration::ImplicitWithDevice}) {
    if (name == toString(c)) return c;
  }
  throw Error("unknown coupling integration '" + name + "' (explicit, implicit, implicit-device)");
}

void checkCouplingDeviceModel(const CouplingDeviceModel& m) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  const auto nonNegative = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!positive(m.mass) || !m.inertiaDiagonal.allFinite() || !positive(m.inertiaDiagonal.minCoeff()))
    throw Error("implicit coupling: the device model's mass and inertia must be positive and finite");
  if (!nonNegative(m.linearFriction) || !nonNegative(m.angularFriction))
    throw Error("implicit coupling: the device model's friction must be finite and >= 0");
}

namespace {

/// The coupling wrench on the object at the end of the tick, to first order (F_c+ of implicit_coupling.h).
Vec6 couplingAtEnd(const CouplingWrench& c, double h, const Vec6& objectTwist, const Vec6& objectDv,
                   const Vec6& deviceTwist, const Vec6& deviceDv) {
  const Vec6 relativeMove = h * ((objectTwist + objectDv) - (deviceTwist + deviceDv));  // dx_s - dx_h
  return c.onSimulation + c.poseGradient * relativeMove + c.twistGradient * (objectDv - deviceDv);
}

}  // namespace

CoupledStep solveCoupledStep(const CoupledStepInput& in) {
  if (in.coupling == nullptr || in.device == nullptr) throw Error("implicit coupling: missing coupling or device");
  if (in.integration == CouplingIntegration::Explicit) throw Error("implicit coupling: Explicit is not solved here");
  const double h = in.timestep;
  const CouplingWrench& c = *in.coupling;
  const Mat6& k = c.poseGradient;
  const Mat6& d = c.twistGradient;
  const Vec6& vs = in.objectTwist;
  const Vec6 vh = in.device->twist();
  const Mat6 kObject = k + in.contactGradient;
  // The object's block and right-hand side, the device's motion at its present velocity included (dv_h = 0).
  const Mat6 objectBlock = in.objectMass - h * d - (h * h) * kObject;
  const Vec6 objectRhs = h * (c.onSimulation + in.contactWrench + h * (kObject * vs) - h * (k * vh));
  CoupledStep out;
  if (in.integration == CouplingIntegration::Implicit) {
    out.objectVelocityChange = objectBlock.partialPivLu().solve(objectRhs);
  } else {
    if (in.deviceModel == nullptr) throw Error("implicit coupling: ImplicitWithDevice needs the device model");
    const CouplingDeviceModel& m = *in.deviceModel;
    const Mat6 deviceMass = massMatrix(m.mass, worldInertia(in.device->worldFromBody, m.inertiaDiagonal));
    Vec6 ownWrench;  // the device's own friction at the tick's start (explicit, as the emulator integrates it)
    ownWrench << -m.linearFriction * in.device->linearVelocity, -m.angularFriction * in.device->angularVelocity;
    const Mat6 cross = h * d + (h * h) * k;
    Eigen::Matrix<double, 12, 12> a;
    a << objectBlock, cross, cross, deviceMass - h * d - (h * h) * k;
    Eigen::Matrix<double, 12, 1> rhs;
    rhs << objectRhs, h * (ownWrench - c.onSimulation - h * (k * vs) + h * (k * vh));
    const Eigen::Matrix<double, 12, 1> dv = a.partialPivLu().solve(rhs);
    out.objectVelocityChange = dv.head<6>();
    out.deviceVelocityChange = dv.tail<6>();
  }
  out.solved = out.objectVelocityChange.allFinite() && out.deviceVelocityChange.allFinite();
  out.wrenchOnDevice = -couplingAtEnd(c, h, vs, out.objectVelocityChange, vh, out.deviceVelocityChange);
  return out;
}

}  // namespace sdfccd::haptics
