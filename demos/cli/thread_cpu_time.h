/// @file
/// @brief threadCpuSeconds(): CPU time of the calling thread, the clock of the benchmarks and the report.
///
/// @details The machine may be shared with other processes; wall time would count their work too, the thread's
/// CPU time does not. std::chrono has no per-thread CPU clock, hence POSIX clock_gettime.
#pragma once

#include <ctime>

namespace sdfccd::cli {

/// CPU time consumed by the calling thread so far (s).
inline double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace sdfccd::cli
