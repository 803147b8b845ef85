/// @file
/// @brief NarrowphasePool (see narrowphase_pool.h).
#include "parallel/narrowphase_pool.h"

#include <cassert>
#include <chrono>

namespace sdfccd::bullet::detail {

int resolveThreads(int threads) {
  if (threads > 0) return threads;
  const unsigned hardware = std::thread::hardware_concurrency();
  return hardware > 0 ? static_cast<int>(hardware) : 1;
}

NarrowphasePool::NarrowphasePool(int threads) : m_threads(resolveThreads(threads)) {
  try {
    for (int i = 1; i < m_threads; ++i) m_workers.emplace_back([this] { workerLoop(); });
  } catch (...) {
    stopWorkers();  // the destructor does not run for a constructor that throws: join what was started
    throw;
  }
}

NarrowphasePool::~NarrowphasePool() {
  stopWorkers();
}

void NarrowphasePool::stopWorkers() {
  {
    const std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_wake.notify_all();
  for (std::thread& worker : m_workers) worker.join();
  m_workers.clear();
}

namespace {
/// How long a thread that finds no published task spins before it sleeps (a sleeping worker costs the stepping
/// thread a futex wake-up at the next publish). Short: 50 us halved the wake-ups while planning but, on a loaded
/// machine, a spinning worker takes the core from the stepping thread (measured slower).
constexpr std::chrono::microseconds kPublishSpin{3};
/// How long close() spins for the workers' last tasks before it sleeps.
constexpr std::chrono::microseconds kDoneSpin{20};

/// The back half of NarrowphasePool::m_claims while the batch is open (the front stops at m_published).
constexpr std::uint64_t kOpen = 0xFFFFFFFFu;
inline std::size_t frontOf(std::uint64_t claims) {
  return static_cast<std::size_t>(claims & 0xFFFFFFFFu);
}
inline std::size_t backOf(std::uint64_t claims) {
  return static_cast<std::size_t>(claims >> 32);
}
inline std::uint64_t claimsOf(std::uint64_t front, std::uint64_t back) {
  return front | (back << 32);
}

inline void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}
}  // namespace

void NarrowphasePool::awaitTasks(std::size_t i) {
  const auto spinEnd = std::chrono::steady_clock::now() + kPublishSpin;
  for (int spin = 1;; ++spin) {
    if (m_closed.load() || m_published.load() > i || frontOf(m_claims.load()) != i) return;
    cpuRelax();
    if (spin % 32 == 0 && std::chrono::steady_clock::now() > spinEnd) break;
  }
  std::unique_lock<std::mutex> lock(m_mutex);
  m_sleepers.fetch_add(1);  // before the predicate's check: publish() sees it, or the check sees its count
  m_more.wait(lock, [&] { return m_closed.load() || m_published.load() > i || frontOf(m_claims.load()) != i; });
  m_sleepers.fetch_sub(1);
}

void NarrowphasePool::drain(const std::function<void(std::size_t)>& task) {
  for (;;) {
    std::uint64_t claims = m_claims.load();
    const std::size_t i = frontOf(claims);
    if (i >= backOf(claims)) return;  // every task claimed (the back is set only when the batch is closed)
    if (i >= m_published.load()) {
      if (m_closed.load()) continue;  // closed meanwhile: the back is set, look again
      awaitTasks(i);
      continue;
    }
    if (!m_claims.compare_exchange_weak(claims, claims + 1)) continue;  // another claim came first: look again
    task(i);
    finishOne();
  }
}

void NarrowphasePool::drainBack(const std::function<void(std::size_t)>& task) {
  for (;;) {
    std::uint64_t claims = m_claims.load();
    const std::size_t front = frontOf(claims);
    const std::size_t back = backOf(claims);
    if (front >= back) return;
    if (!m_claims.compare_exchange_weak(claims, claimsOf(front, back - 1))) continue;
    task(back - 1);
    finishOne();
  }
}

void NarrowphasePool::finishOne() {
  if (m_finished.fetch_add(1) + 1 == m_published.load() && m_closed.load()) {
    const std::lock_guard<std::mutex> lock(m_mutex);  // the caller checks under the lock: no lost wake-up
    m_done.notify_all();
  }
}

void NarrowphasePool::workerLoop() {
  std::uint64_t seen = 0;
  std::unique_lock<std::mutex> lock(m_mutex);
  for (;;) {
    m_wake.wait(lock, [&] { return m_stop || m_generation != seen; });
    if (m_stop) return;
    seen = m_generation;
    if (!m_accepting) continue;  // woke after its batch ended
    ++m_active;
    const std::function<void(std::size_t)>* task = m_task;
    lock.unlock();
    drain(*task);
    lock.lock();
    --m_active;
    m_done.notify_all();
  }
}

void NarrowphasePool::begin(const std::function<void(std::size_t)>& task) {
  {
    const std::lock_guard<std::mutex> lock(m_mutex);
    m_task = &task;
    m_claims = claimsOf(0, kOpen);
    m_published = 0;
    m_closed = false;
    m_finished = 0;
    if (m_workers.empty()) return;
    m_accepting = true;
    ++m_generation;
  }
  m_wake.notify_all();  // after unlocking: a woken worker does not block on the mutex at once
}

void NarrowphasePool::publish(std::size_t count) {
  if (m_workers.empty() || count <= m_published.load()) return;
  m_published.store(count);
  // Only a sleeper needs the lock and the wake-up. Both counters are sequentially consistent: either a worker
  // about to sleep sees the new count in its predicate, or this sees it among the sleepers. A sleeper holds the
  // lock from its count to its wait, so taking the lock here orders the notification after its wait began.
  if (m_sleepers.load() == 0) return;
  { const std::lock_guard<std::mutex> lock(m_mutex); }
  m_more.notify_all();
}

void NarrowphasePool::close(std::size_t total) {
  const std::function<void(std::size_t)>* task = m_task;
  // Both ends of the claims share a 64-bit word (m_claims): a batch holds fewer than 2^32 - 1 tasks (a step's has
  // two per pair, and Bullet counts its pairs in an int: at most 2^32 - 2).
  assert(total < kOpen);
  if (m_workers.empty()) {
    for (std::size_t i = 0; i < total; ++i) (*task)(i);
    m_task = nullptr;
    return;
  }
  {
    const std::lock_guard<std::mutex> lock(m_mutex);
    m_published = total;
    // The back end: from now on the caller claims there (the workers' front claims may change the word meanwhile).
    std::uint64_t claims = m_claims.load();
    while (!m_claims.compare_exchange_weak(claims, claimsOf(frontOf(claims), total))) {
    }
    m_closed = true;
  }
  m_more.notify_all();
  drainBack(*task);
  // The workers' last tasks: spin a little before sleeping (a sleep and its wake-up cost the stepping thread tens
  // of microseconds on a virtual machine, more than most tasks take).
  const auto spinEnd = std::chrono::steady_clock::now() + kDoneSpin;
  for (int spin = 1; !(m_finished.load() == total && m_active.load() == 0); ++spin) {
    cpuRelax();
    if (spin % 32 == 0 && std::chrono::steady_clock::now() > spinEnd) break;
  }
  std::unique_lock<std::mutex> lock(m_mutex);
  m_done.wait(lock, [&] { return m_finished.load() == total; });
  // Workers that joined may still be between their last claim and leaving: the batch (and `task`) outlives them.
  m_accepting = false;
  m_done.wait(lock, [&] { return m_active == 0; });
  m_task = nullptr;
}

void NarrowphasePool::run(std::size_t count, const std::function<void(std::size_t)>& task) {
  if (m_workers.empty() || count < 2) {
    for (std::size_t i = 0; i < count; ++i) task(i);
    return;
  }
  begin(task);
  close(count);
}

}  // namespace sdfccd::bullet::detail
