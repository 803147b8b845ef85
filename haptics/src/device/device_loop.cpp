/// @file
/// @brief DeviceLoop: the fixed-rate loop of a haptic device (see haptic_device.h).
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>

#include "sdfccd/error.h"
#include "sdfccd/haptics/haptic_device.h"

namespace sdfccd::haptics {

double percentile(std::vector<double> samples, double percent) {
  if (samples.empty()) return 0.0;
  const double rank = std::clamp(percent, 0.0, 100.0) / 100.0 * static_cast<double>(samples.size() - 1);
  const auto k = static_cast<std::size_t>(std::lround(rank));
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(k), samples.end());
  return samples[k];
}

namespace {

/// Asks for SCHED_FIFO at `priority` for the calling thread; returns what the system said, for the summary.
std::string requestRealTimePriority(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  const std::string what = "(SCHED_FIFO " + std::to_string(priority) + ")";
  if (rc == 0) return "granted " + what;
  return "denied " + what + ": " + std::strerror(rc);
}

}  // namespace

DeviceLoop::~DeviceLoop() {
  stop();
}

void DeviceLoop::tick(const TickHandler& handler) {
  Vec6 w = Vec6::Zero();
  try {
    if (handler) w = handler(m_device.state());
  } catch (const std::exception& e) {
    m_error = e.what();
  } catch (...) {
    m_error = "unknown exception";
  }
  if (!m_error.empty()) {
    // The device must not keep rendering a stale force: zero for this tick, and the loop ends after it.
    w.setZero();
    requestStop();
  }
  try {
    m_device.write(w);
  } catch (const std::exception& e) {
    if (m_error.empty()) m_error = std::string("device write: ") + e.what();
    requestStop();
  } catch (...) {
    if (m_error.empty()) m_error = "device write: unknown exception";
    requestStop();
  }
}

LoopTimingStats DeviceLoop::runVirtual(std::int64_t ticks, const TickHandler& handler) {
  if (running()) throw Error("device loop: runVirtual while the real-time loop runs");
  LoopTimingStats stats;
  stats.virtualTime = true;
  m_error.clear();
  m_stopRequested.store(false);
  std::int64_t n = 0;
  for (; n < ticks && !stopRequested() && m_device.ticksLeft() != 0; ++n) tick(handler);
  stats.ticks = n;
  stats.elapsedSeconds = static_cast<double>(n) * m_device.period();
  stats.achievedRateHz = m_device.rateHz();
  m_stats = stats;
  return stats;
}

void DeviceLoop::start(TickHandler handler, std::int64_t maxTicks, const DeviceLoopOptions& options) {
  if (m_thread.joinable()) throw Error("device loop: the loop is already running");
  if (options.realTimePriority && (options.priority < 1 || options.priority > 99))
    throw Error("device loop: real-time priority must be in 1..99");
  m_handler = std::move(handler);
  m_error.clear();
  m_stopRequested.store(false);
  m_running.store(true, std::memory_order_release);
  m_thread = std::thread([this, maxTicks, options] { loop(maxTicks, options); });
}

void DeviceLoop::stop() {
  m_stopRequested.store(true);
  if (m_thread.joinable()) m_thread.join();
}

void DeviceLoop::wait() {
  if (m_thread.joinable()) m_thread.join();
}

void DeviceLoop::loop(std::int64_t maxTicks, DeviceLoopOptions options) {
  using Clock = std::chrono::steady_clock;
  LoopTimingStats stats;
  if (options.realTimePriority) stats.realTimePriority = requestRealTimePriority(options.priority);
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(m_device.period()));
  std::vector<double> lateness;
  std::vector<double> busy;
  lateness.reserve(static_cast<std::size_t>(std::min<std::int64_t>(maxTicks, 10'000'000)));
  busy.reserve(lateness.capacity());
  const auto begin = Clock::now();
  auto deadline = begin;
  std::int64_t n = 0;
  for (; n < maxTicks && !stopRequested() && m_device.ticksLeft() != 0; ++n) {
    std::this_thread::sleep_until(deadline);
    const auto woke = Clock::now();
    lateness.push_back(std::chrono::duration<double, std::micro>(woke - deadline).count());
    tick(m_handler);
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
