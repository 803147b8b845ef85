/// @file
/// @brief NarrowphasePool: the persistent worker pool of the parallel narrowphase (issue 17 item 1).
///
/// @details A oneTBB task arena of a fixed concurrency. TBB's workers are created once per process and parked
/// between calls, so a 1 ms step pays a wake-up, not a thread start (the core's parallel_for starts threads on
/// every call: too costly here). One thread runs the tasks on the caller, in index order, without TBB.
/// The tasks must be independent: which thread runs which index is not fixed, so each task writes only its own
/// output (results are then bit-identical for any thread count).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace sdfccd::detail {

class NarrowphasePool {
 public:
  /// `threads`: 1 = serial on the caller; 0 = the machine's hardware threads.
  explicit NarrowphasePool(int threads);
  ~NarrowphasePool();
  NarrowphasePool(const NarrowphasePool&) = delete;
  NarrowphasePool& operator=(const NarrowphasePool&) = delete;

  int threads() const { return m_threads; }
  /// Runs task(i) for i in [0, count), each index once, and returns when all are done.
  void run(std::size_t count, const std::function<void(std::size_t)>& task);

 private:
  struct Arena;
  int m_threads = 1;
  std::unique_ptr<Arena> m_arena;  // null for one thread
};

/// The threads a `threads` setting means: the hardware's for 0 (at least 1), else the value.
int resolveThreads(int threads);

}  // namespace sdfccd::detail
