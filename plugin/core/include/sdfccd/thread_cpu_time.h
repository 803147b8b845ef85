/// @file
/// @brief threadCpuSeconds(): CPU time of the calling thread, the one clock of the timings in sdfccd (the CCD
/// statistics of the Bullet contact system, the haptic cycle log, the benchmarks and the report).
///
/// @details The machine may be shared with other processes; wall time would count their work too, the thread's
/// CPU time does not. std::chrono has no per-thread CPU clock, hence POSIX clock_gettime with
/// CLOCK_THREAD_CPUTIME_ID (Linux; nanosecond resolution). Thread safe: it reads the calling thread's clock only.
#pragma once

#include <ctime>

namespace sdfccd {

/// CPU time consumed by the calling thread so far (s). Only differences of two calls on the same thread mean
/// something.
inline double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace sdfccd
