/// @file
/// @brief NarrowphasePool: the persistent worker pool of the parallel narrowphase (step_planner.h).
///
/// @details Threads started once (with the contact system's settings) and parked on a condition variable between
/// steps, so a 1 ms step pays a wake-up, not a thread start (the core's parallel_for starts threads on every call:
/// too costly here). The tasks of a batch are claimed one at a time from an atomic counter, by the workers and by
/// the calling thread alike (load balance: the roles' costs differ by orders of magnitude).
/// Why not oneTBB: its synchronisation lives in the uninstrumented Debian library, so ThreadSanitizer cannot see
/// the hand-over of a task to a worker and reports races that are not there; and its workers spin before they
/// park, which on a shared, loaded machine takes CPU from the others. Here every hand-over is a std::mutex or a
/// std::atomic, which TSan sees.
/// The tasks must be independent: which thread runs which index is not fixed, so each task writes only its own
/// output (results are then bit-identical for any thread count). One batch at a time (run() is not reentrant).
/// A batch may also be streamed (begin, publish, close): the workers start on the first tasks while the caller
/// still prepares the next ones (the step's planning pass, serial, overlaps the CCD of the pairs planned so far).
/// The workers claim tasks from the front, the caller (when it closes the batch) from the back. A batch holds
/// fewer than 2^32 - 1 tasks (both ends share one 64-bit atomic).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace sdfccd::bullet::detail {

class NarrowphasePool {
 public:
  /// `threads` in all, the caller included: 1 = serial on the caller; 0 = the machine's hardware threads.
  explicit NarrowphasePool(int threads);
  ~NarrowphasePool();
  NarrowphasePool(const NarrowphasePool&) = delete;
  NarrowphasePool& operator=(const NarrowphasePool&) = delete;

  int threads() const { return m_threads; }
  /// Runs task(i) for i in [0, count), each index once, and returns when all are done.
  void run(std::size_t count, const std::function<void(std::size_t)>& task);
  /// A streamed batch: begin(task) opens it (`task` must outlive it), publish(n) makes tasks [0, n) available
  /// (n never decreases; the caller must have finished writing what they read), close(total) publishes the last
  /// ones, runs tasks with the workers and returns when all `total` are done. With no workers, close runs them all.
  void begin(const std::function<void(std::size_t)>& task);
  void publish(std::size_t count);
  void close(std::size_t total);

 private:
  void workerLoop();
  void stopWorkers();  ///< stops and joins every worker (the destructor, and a constructor that fails)
  /// Claims and runs published tasks of the current batch until it is closed and none is left.
  void drain(const std::function<void(std::size_t)>& task);
  /// Waits (spins briefly, then sleeps) until task `i` may be published, claimed by another thread, or the batch
  /// closed; `i` is the next task to claim that this thread saw unpublished.
  void awaitTasks(std::size_t i);
  /// Claims and runs tasks at the back until none is left (close()).
  void drainBack(const std::function<void(std::size_t)>& task);
  /// One task has run (a claim at either end): counts it, and wakes the caller when it was the batch's last.
  void finishOne();

  int m_threads = 1;
  std::vector<std::thread> m_workers;
  std::mutex m_mutex;
  std::condition_variable m_wake;  // workers: a new batch, or stop
  std::condition_variable m_done;  // the caller: a task or a worker finished
  std::condition_variable m_more;  // workers inside a batch: tasks published, or the batch closed
  // The batch, under m_mutex (the counters are atomic: claimed and finished outside it).
  const std::function<void(std::size_t)>* m_task = nullptr;
  std::uint64_t m_generation = 0;
  bool m_accepting = false;      // a worker that wakes after its batch ended must not join it
  std::atomic<int> m_active{0};  // workers inside the current batch (changed under m_mutex; close() spins on it)
  bool m_stop = false;
  // What the claiming threads write on every task, apart from what the publisher writes (false sharing).
  // The tasks still to claim are [front, back): the workers claim at the front, the caller, once it closes the
  // batch, at the back. A task then tends to run on the same thread step after step (the pairs come in Bullet's
  // order every step), so what it reads and writes (a pair's CCD history, its anchors) stays in that core's cache;
  // claimed from one end by both, the half the caller took landed on either core at random. Both ends in one word,
  // so that a claim at either end sees the other: the low half is the front, the high half the back (kOpen until
  // close() sets it; the front then stops at m_published).
  alignas(64) std::atomic<std::uint64_t> m_claims{0};
  std::atomic<std::size_t> m_finished{0};
  alignas(64) std::atomic<std::size_t> m_published{0};  // tasks [0, m_published) may be claimed
  std::atomic<bool> m_closed{false};                    // m_published is the batch's total
  std::atomic<int> m_sleepers{0};  // threads waiting on m_more (publish() wakes only when there are some)
};

/// The threads a `threads` setting means: the hardware's for 0 (at least 1), else the value.
int resolveThreads(int threads);

}  // namespace sdfccd::bullet::detail
