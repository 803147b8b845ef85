/// @file
/// @brief TwoLoopRunner: the haptic loop and the simulation loop on any device (see two_loop_runner.h).
#include "sdfccd/haptics/two_loop_runner.h"

#include <exception>
#include <thread>

#include "sdfccd/error.h"
#include "sdfccd/haptics/latest_value.h"

namespace sdfccd::haptics {

namespace {

/// Runs `body`, turning any exception into an sdfccd::Error whose message names the loop.
template <class Body>
auto named(const char* loop, const Body& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    throw Error(std::string(loop) + ": " + e.what());
  } catch (...) {
    throw Error(std::string(loop) + ": unknown exception");
  }
}

}  // namespace

TwoLoopRunner::TwoLoopRunner(HapticDevice& device, const TwoLoopSettings& settings)
    : m_device(device), m_settings(settings) {
  if (settings.ticks < 0) throw Error("two-loop runner: ticks must be >= 0");
  if (settings.simCyclesPerTick < 1 || settings.simCyclesPerTick > 1000)
    throw Error("two-loop runner: simCyclesPerTick must be in [1, 1000]");
}

TwoLoopResult TwoLoopRunner::run(const SimulationCycle& simulate, const TickHandler& haptic) {
  if (!haptic) throw Error("two-loop runner: no haptic tick");
  m_stop.store(false);
  return m_settings.realTime ? runRealTime(simulate, haptic) : runVirtual(simulate, haptic);
}

TwoLoopResult TwoLoopRunner::runVirtual(const SimulationCycle& simulate, const TickHandler& haptic) {
  DeviceLoop loop(m_device);
  TwoLoopResult result;
  result.timing = loop.runVirtual(m_settings.ticks, [&](const DeviceState& state) {
    if (simulate) {
      named("simulation loop", [&] {
        for (int n = 0; n < m_settings.simCyclesPerTick; ++n, ++result.simulationCycles) simulate(state);
        return 0;
      });
    }
    const Vec6 w = named("haptic loop", [&] { return haptic(state); });
    if (m_stop.load(std::memory_order_relaxed)) loop.requestStop();
    return w;
  });
  result.error = loop.error();
  return result;
}

TwoLoopResult TwoLoopRunner::runRealTime(const SimulationCycle& simulate, const TickHandler& haptic) {
  DeviceLoop loop(m_device);
  TwoLoopResult result;
  LatestValue<DeviceState> deviceState;
  deviceState.publish(m_device.state());
  std::atomic<bool> simulationDone{false};
  std::atomic<bool> simulationFailed{false};
  std::string simulationError;  // written by the simulation thread before simulationFailed (release)
  std::int64_t cycles = 0;      // read after the join
  std::thread simulation;
  if (simulate) {
    simulation = std::thread([&] {
      DeviceState state;
      std::uint64_t lastSequence = 0;
      bool idle = false;
      while (!simulationDone.load(std::memory_order_acquire)) {
        const std::uint64_t sequence = deviceState.read(state);
        if (idle && sequence == lastSequence) {
          // Settled and the device has not moved: give the core back (it is shared with the haptic loop).
          std::this_thread::yield();
          continue;
        }
        lastSequence = sequence;
        try {
          idle = !simulate(state);
          ++cycles;
        } catch (const std::exception& e) {
          simulationError = std::string("simulation loop: ") + e.what();
        } catch (...) {
          simulationError = "simulation loop: unknown exception";
        }
        if (!simulationError.empty()) {
          simulationFailed.store(true, std::memory_order_release);
          return;
        }
      }
    });
  }
  // The simulation thread is joined on every path: a device loop that cannot start (bad loop options, a thread
  // that cannot be created) throws here, and a joinable std::thread destroyed during unwinding would terminate.
  const auto stopSimulation = [&] {
    simulationDone.store(true, std::memory_order_release);
    if (simulation.joinable()) simulation.join();
  };
  try {
    loop.start(
        [&](const DeviceState& state) {
          deviceState.publish(state);
          // The simulation failed: this tick renders zero (the loop writes zero on a throw) and the loop ends.
          if (simulationFailed.load(std::memory_order_acquire)) throw Error(simulationError);
          const Vec6 w = named("haptic loop", [&] { return haptic(state); });
          if (m_stop.load(std::memory_order_relaxed)) loop.requestStop();
          return w;
        },
        m_settings.ticks, m_settings.loop);
  } catch (...) {
    stopSimulation();
    throw;
  }
  loop.wait();
  stopSimulation();
  result.timing = loop.stats();
  result.error = loop.error();
  if (result.error.empty() && simulationFailed.load()) {
    // The simulation failed after the last tick: nothing was rendered from its output, but the session failed.
    result.error = simulationError;
  }
  result.simulationCycles = cycles;
  return result;
}

}  // namespace sdfccd::haptics
