/// @file
/// @brief The constraint methods' simulation cycle and haptic tick, stage by stage (see session_stages.h).
#include <algorithm>
#include <string>

#include "sdfccd/error.h"
#include "session/session_stages.h"

namespace sdfccd::haptics {

ConstraintLoops::ConstraintLoops(const HapticScene& scene, const SessionFaults& faults, GodObject& god,
                                 SimulationLog& log, DevicePort& port)
    : m_scene(scene), m_faults(faults), m_god(god), m_log(log), m_port(port) {
  // A moving obstacle keeps the simulation busy even while the device and the god-object are still.
  m_movingObstacles = std::any_of(scene.obstacles.begin(), scene.obstacles.end(),
                                  [](const HapticObstacle& o) { return o.path.moving(); });
  SimulationOutput initial;
  initial.worldFromSimulation = scene.worldFromBodyStart;
  m_simulation.publish(initial);
}

bool ConstraintLoops::simulationCycle(const DeviceState& device) {
  injectFault();
  const GodObjectStepResult r = stepGodObject(device);
  const SimulationOutput out = measure(r);
  publish(out);
  return !out.idle;
}

Vec6 ConstraintLoops::hapticTick(const DeviceState& state) {
  const SimulationOutput sim = newestSimulation();
  const bool stop = m_port.guard().observePose(state.time, sim.worldFromSimulation);
  return m_port.render(state, sim, stop);
}

// The test seam (fault_injection.h): the cycle with the chosen index throws.
void ConstraintLoops::injectFault() const {
  if (m_faults.simulationCycle >= 0 && static_cast<std::int64_t>(m_log.cycleMs.size()) >= m_faults.simulationCycle)
    throw Error("injected fault at simulation cycle " + std::to_string(m_log.cycleMs.size()));
}

// Timed: the obstacles moved to the device tick's time, the QP and the CCD.
GodObjectStepResult ConstraintLoops::stepGodObject(const DeviceState& device) {
  m_god.setObstacleTime(device.time);
  return m_log.timed([&] { return m_god.step(device.body.worldFromBody); });
}

// Untimed: the penetration at the pose reached, the cycle's QP outcome in the log.
SimulationOutput ConstraintLoops::measure(const GodObjectStepResult& r) {
  SimulationOutput out =
      m_log.measure(m_scene, r.wrenchOnDevice, m_god.pose(), r.nextContactCount, m_god.penetration());
  out.qpState = static_cast<int>(r.qpState);
  out.idle = r.fraction * r.constrained.norm() < 1e-9 * m_scene.cellSize && !m_movingObstacles;
  m_log.stuck += r.qpState == ContactQpState::Stuck || r.squeezed;
  m_log.failed += r.qpState == ContactQpState::Failed;
  m_log.blocked += r.blocked;
  return out;
}

SimulationOutput ConstraintLoops::newestSimulation() {
  SimulationOutput sim;
  m_simulation.read(sim);
  return sim;
}

}  // namespace sdfccd::haptics
