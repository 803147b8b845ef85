/// @file
/// @brief The penalty methods' haptic tick, stage by stage (see session_stages.h).
#include <string>

#include "sdfccd/error.h"
#include "session/session_stages.h"

namespace sdfccd::haptics {

PenaltyLoop::PenaltyLoop(const HapticScene& scene, const SessionFaults& faults, PenaltyRenderer& renderer,
                         SimulationLog& log, DevicePort& port)
    : m_scene(scene), m_faults(faults), m_renderer(renderer), m_log(log), m_port(port) {}

Vec6 PenaltyLoop::hapticTick(const DeviceState& state) {
  injectFault(state);
  const PenaltyStepResult r = stepRenderer(state);
  const SimulationOutput sim = measure(r);
  const bool stop = m_port.guard().observeState(state.time, m_renderer.state());
  return m_port.render(state, sim, stop);
}

// The test seam (fault_injection.h): the tick with the chosen number throws.
void PenaltyLoop::injectFault(const DeviceState& state) const {
  if (m_faults.hapticTick >= 0 && state.tick >= m_faults.hapticTick)
    throw Error("injected fault at haptic tick " + std::to_string(state.tick));
}

// Timed: the obstacles over the tick, the implicit step and the contacts of the step taken.
PenaltyStepResult PenaltyLoop::stepRenderer(const DeviceState& state) {
  m_renderer.setObstacleTime(state.time);
  return m_log.timed([&] { return m_renderer.step(state.body); });
}

// Untimed: the penetration at the pose reached.
SimulationOutput PenaltyLoop::measure(const PenaltyStepResult& r) {
  return m_log.measure(m_scene, r.wrenchOnDevice, m_renderer.state().worldFromBody, r.contactCount,
                       m_renderer.penetration());
}

}  // namespace sdfccd::haptics
