/// @file
/// @brief The end of every haptic tick (DevicePort) and what a simulation step hands the haptic loop
/// (SimulationLog::measure); see session_stages.h.
#include <algorithm>
#include <vector>

#include "session/session_stages.h"

namespace sdfccd::haptics {

namespace {

/// The device port's passivity settings: the session's (the observer alone when passivity is off, so that the
/// port's energy account is still kept), within the device's own force and torque limits.
PassivitySettings portPassivity(const HapticScene& scene, const HapticSessionSettings& settings) {
  PassivitySettings p = settings.passivityEnabled ? settings.passivity : PassivitySettings{};
  p.controller = settings.passivityEnabled && p.controller;
  p.maxForce = std::min(p.maxForce, scene.device.maxForce);
  p.maxTorque = std::min(p.maxTorque, scene.device.maxTorque);
  return p;
}

}  // namespace

SimulationOutput SimulationLog::measure(const HapticScene& scene, const Vec6& wrenchOnDevice,
                                        const Rigid& worldFromSimulation, int contacts, double penetration) {
  SimulationOutput out;
  out.cycleMs = cycleMs.back();
  out.wrenchOnDevice = wrenchOnDevice;
  out.worldFromSimulation = worldFromSimulation;
  out.contacts = contacts;
  out.penetration = penetration;
  maxContacts = std::max(maxContacts, contacts);
  contactSum += contacts;
  maxPenetration = std::max(maxPenetration, penetration);
  const Vec3 c = worldFromSimulation.translation();
  if (scene.checks.hasInsert) {
    const double reach = scene.checks.insertAxis.dot(c);
    insertProgress = std::max(insertProgress, reach);
    if (reach >= scene.checks.insertDepth) inserted = true;
  }
  if (scene.checks.hasTunnel && scene.checks.tunnelNormal.dot(c) > scene.checks.tunnelOffset) tunneled = true;
  return out;
}

DevicePort::DevicePort(const HapticScene& scene, const HapticSessionSettings& settings,
                       std::vector<HapticTickRecord>& ticks)
    : m_guard(scene),
      m_passivity(portPassivity(scene, settings)),
      m_recordTicks(settings.recordTicks),
      m_ticks(ticks) {}

Vec6 DevicePort::render(const DeviceState& state, SimulationOutput sim, bool stop) {
  if (stop) {
    sim.wrenchOnDevice = Vec6::Zero();
    m_runner->requestStop();
  } else {
    sim.wrenchOnDevice = m_passivity.filter(state, sim.wrenchOnDevice);
  }
  record(state, sim);
  return sim.wrenchOnDevice;
}

void DevicePort::record(const DeviceState& state, const SimulationOutput& sim) {
  if (!m_recordTicks) return;
  HapticTickRecord row;
  row.tick = state.tick;
  row.time = state.time;
  row.worldFromDevice = state.body.worldFromBody;
  row.worldFromSimulation = sim.worldFromSimulation;
  row.wrenchOnDevice = sim.wrenchOnDevice;
  row.contacts = sim.contacts;
  row.penetration = sim.penetration;
  row.qpState = sim.qpState;
  row.simCycleMs = sim.cycleMs;
  m_ticks.push_back(row);
}

}  // namespace sdfccd::haptics
