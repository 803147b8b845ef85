/// @file
/// @brief NarrowphasePool (see narrowphase_pool.h).
#include "narrowphase_pool.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <thread>

namespace sdfccd::detail {

struct NarrowphasePool::Arena {
  explicit Arena(int threads) : arena(threads) {}
  tbb::task_arena arena;
};

int resolveThreads(int threads) {
  if (threads > 0) return threads;
  const unsigned hardware = std::thread::hardware_concurrency();
  return hardware > 0 ? static_cast<int>(hardware) : 1;
}

NarrowphasePool::NarrowphasePool(int threads) : m_threads(resolveThreads(threads)) {
  if (m_threads > 1) m_arena = std::make_unique<Arena>(m_threads);
}

NarrowphasePool::~NarrowphasePool() = default;

void NarrowphasePool::run(std::size_t count, const std::function<void(std::size_t)>& task) {
  if (!m_arena || count < 2) {
    for (std::size_t i = 0; i < count; ++i) task(i);
    return;
  }
  // Grain 1: a task is one CCD role (tens of microseconds to milliseconds), and their costs differ widely.
  m_arena->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) task(i);
    });
  });
}

}  // namespace sdfccd::detail
