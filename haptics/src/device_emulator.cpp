/// @file
/// @brief DeviceEmulator: the emulated 6-DoF manipulandum and its fixed-rate loop.
#include "sdfccd/haptics/device_emulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "sdfccd/error.h"

namespace sdfccd::haptics {

namespace {

Vec3 clampNorm(const Vec3& v, double limit) {
  const double n = v.norm();
  return n > limit ? Vec3(v * (limit / n)) : v;
}

}  // namespace

double percentile(std::vector<double> samples, double percent) {
  if (samples.empty()) return 0.0;
  const double rank = std::clamp(percent, 0.0, 100.0) / 100.0 * static_cast<double>(samples.size() - 1);
  const auto k = static_cast<std::size_t>(std::lround(rank));
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(k), samples.end());
  return samples[k];
}

DeviceEmulator::DeviceEmulator(const DeviceSettings& settings, UserScript script, const Rigid& worldFromDeviceStart)
    : m_settings(settings), m_script(std::move(script)) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  const auto nonNegative = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!positive(settings.rateHz) || settings.rateHz > 1e6) throw Error("device: rate must be in (0, 1e6] Hz");
  if (!positive(settings.mass) || !positive(settings.inertiaDiagonal.minCoeff()) ||
      !settings.inertiaDiagonal.allFinite())
    throw Error("device: mass and inertia must be positive and finite");
  if (!positive(settings.maxForce) || !positive(settings.maxTorque))
    throw Error("device: force and torque limits must be positive and finite");
  if (!nonNegative(settings.linearFriction) || !nonNegative(settings.angularFriction) ||
      !nonNegative(settings.userStiffness) || !nonNegative(settings.userDamping) ||
      !nonNegative(settings.userAngularStiffness) || !nonNegative(settings.userAngularDamping))
    throw Error("device: friction, stiffness and damping must be non-negative and finite");
  if (!worldFromDeviceStart.matrix().allFinite()) throw Error("device: start pose is not finite");
  m_state.body.worldFromBody = worldFromDeviceStart;
  m_state.worldFromTarget = m_script.targetAt(0.0);
}

DeviceEmulator::~DeviceEmulator() {
  stop();
}

void DeviceEmulator::step(const Vec6& renderedWrench) {
  const double dt = timestep();
  RigidBodyState& b = m_state.body;
  const Rigid target = m_script.targetAt(m_state.time);
  const Vec6 toTarget = poseDifference(b.worldFromBody, target);
  Vec6 user;
  user.head<3>() = m_settings.userStiffness * toTarget.head<3>() - m_settings.userDamping * b.linearVelocity;
  user.tail<3>() =
      m_settings.userAngularStiffness * toTarget.tail<3>() - m_settings.userAngularDamping * b.angularVelocity;
  Vec6 rendered = renderedWrench.allFinite() ? renderedWrench : Vec6::Zero();  // a bad wrench renders nothing
  rendered.head<3>() = clampNorm(rendered.head<3>(), m_settings.maxForce);
  rendered.tail<3>() = clampNorm(rendered.tail<3>(), m_settings.maxTorque);

  const Vec3 force = user.head<3>() + rendered.head<3>() - m_settings.linearFriction * b.linearVelocity;
  const Vec3 torque = user.tail<3>() + rendered.tail<3>() - m_settings.angularFriction * b.angularVelocity;
  const Mat3 inertia = worldInertia(b.worldFromBody, m_settings.inertiaDiagonal);
  // Symplectic Euler: velocities first, then the pose with the new velocities.
  b.linearVelocity += dt / m_settings.mass * force;
  b.angularVelocity += dt * inertia.ldlt().solve(torque - b.angularVelocity.cross(inertia * b.angularVelocity));
  Vec6 move;
  move << dt * b.linearVelocity, dt * b.angularVelocity;
  b.worldFromBody = displacePose(b.worldFromBody, move);

  m_state.userWrench = user;
  m_state.renderedWrench = rendered;
  m_state.worldFromTarget = target;
  ++m_state.tick;
  m_state.time = static_cast<double>(m_state.tick) * dt;
}

LoopTimingStats DeviceEmulator::runVirtual(std::int64_t ticks, const TickHandler& handler) {
  if (running()) throw Error("device: runVirtual while the real-time loop runs");
  LoopTimingStats stats;
  stats.virtualTime = true;
  m_stopRequested.store(false);
  std::int64_t n = 0;
  for (; n < ticks && !m_stopRequested.load(std::memory_order_relaxed); ++n) {
    const Vec6 w = handler ? handler(m_state) : Vec6::Zero();
    step(w);
  }
  stats.ticks = n;
  stats.elapsedSeconds = static_cast<double>(n) * timestep();
  stats.achievedRateHz = m_settings.rateHz;
  m_stats = stats;
  return stats;
}

void DeviceEmulator::start(TickHandler handler, std::int64_t maxTicks) {
  if (m_thread.joinable()) throw Error("device: the loop is already running");
  m_handler = std::move(handler);
  m_stopRequested.store(false);
  m_running.store(true, std::memory_order_release);
  m_thread = std::thread([this, maxTicks] { loop(maxTicks); });
}

void DeviceEmulator::stop() {
  m_stopRequested.store(true);
  if (m_thread.joinable()) m_thread.join();
}

void DeviceEmulator::wait() {
  if (m_thread.joinable()) m_thread.join();
}

void DeviceEmulator::loop(std::int64_t maxTicks) {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timestep()));
  std::vector<double> lateness;
  std::vector<double> busy;
  lateness.reserve(static_cast<std::size_t>(std::min<std::int64_t>(maxTicks, 10'000'000)));
  busy.reserve(lateness.capacity());
  LoopTimingStats stats;
  const auto begin = Clock::now();
  auto deadline = begin;
  std::int64_t n = 0;
  for (; n < maxTicks && !m_stopRequested.load(std::memory_order_relaxed); ++n) {
    std::this_thread::sleep_until(deadline);
    const auto woke = Clock::now();
    lateness.push_back(std::chrono::duration<double, std::micro>(woke - deadline).count());
    const Vec6 w = m_handler ? m_handler(m_state) : Vec6::Zero();
    step(w);
    const auto done = Clock::now();
    busy.push_back(std::chrono::duration<double, std::micro>(done - woke).count());
    deadline += period;
    if (done > deadline) {
      ++stats.overruns;
      // Skip the deadlines already missed rather than running a burst of late ticks.
      while (deadline + period < done) deadline += period;
    }
  }
  const auto end = Clock::now();
  stats.ticks = n;
  stats.elapsedSeconds = std::chrono::duration<double>(end - begin).count();
  stats.achievedRateHz = stats.elapsedSeconds > 0.0 ? static_cast<double>(n) / stats.elapsedSeconds : 0.0;
  stats.jitterP50Us = percentile(lateness, 50.0);
  stats.jitterP99Us = percentile(lateness, 99.0);
  stats.jitterMaxUs = lateness.empty() ? 0.0 : *std::max_element(lateness.begin(), lateness.end());
  stats.handlerP99Us = percentile(busy, 99.0);
  m_stats = stats;
  m_running.store(false, std::memory_order_release);
}

}  // namespace sdfccd::haptics
