/// @file
/// @brief parallelFor: run a loop body over [0, count) on worker threads, dynamically load-balanced.
///
/// @details Written on std::thread rather than TBB so that sdfccd::core depends on Eigen alone
/// (docs/architecture.md); the loops it serves are coarse (blocks of grid nodes, subtrees), so a shared atomic
/// counter is all the scheduling they need.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace sdfccd {

/// Number of worker threads to use when the caller passes 0: the hardware concurrency (at least 1).
inline int defaultThreadCount() {
  return std::max(1u, std::thread::hardware_concurrency());
}

/// Calls body(index, threadId) for every index in [0, count), on `threads` threads (0: all cores).
/// threadId is in [0, threads). The first exception thrown by a body is rethrown after all threads stop.
template <class Body>
void parallelFor(std::size_t count, int threads, Body&& body) {
  if (threads <= 0) threads = defaultThreadCount();
  threads = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(threads), std::max<std::size_t>(count, 1)));
  if (threads <= 1) {
    for (std::size_t n = 0; n < count; ++n) body(n, 0);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex errorMutex;
  auto worker = [&](int threadId) {
    try {
      for (std::size_t n = next++; n < count && !failed.load(std::memory_order_relaxed); n = next++) body(n, threadId);
    } catch (...) {
      std::lock_guard<std::mutex> lock(errorMutex);
      if (!error) error = std::current_exception();
      failed = true;
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(threads - 1));
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace sdfccd
