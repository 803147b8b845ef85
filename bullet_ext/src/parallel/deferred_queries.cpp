/// @file
/// @brief DeferredQueries (see deferred_queries.h).
#include "parallel/deferred_queries.h"

#include <atomic>
#include <utility>

#include "parallel/narrowphase_pool.h"

namespace sdfccd::bullet::detail {

std::size_t DeferredQueries::nextArenaIndex() {
  static std::atomic<std::size_t> next{0};
  return next.fetch_add(1);
}

void DeferredQueries::clear() {
  for (const std::unique_ptr<ArenaBase>& arena : m_arenas) {
    if (arena) arena->used = 0;
  }
  m_jobs.clear();
  ++m_generation;  // the outcomes are not reset one by one (their cache lines are the workers')
  m_index.clear();
  m_indexed = false;
  m_cursor = 0;
}

namespace {
/// A streamed batch publishes its queries in groups of this many (one lock and wake-up per group).
constexpr std::size_t kPublishGroup = 8;
}  // namespace

bool DeferredQueries::add(const void* manifold, int role, Compute compute) {
  if (m_streaming != nullptr && m_jobs.size() >= m_capacity) return false;
  Compute& kept = slot<Compute>();
  kept = std::move(compute);
  return add(
      manifold, role, [](const void* data, RoleResult& out) { (*static_cast<const Compute*>(data))(out); }, &kept);
}

bool DeferredQueries::add(const void* manifold, int role, Run run, const void* data) {
  if (m_streaming != nullptr && m_jobs.size() >= m_capacity) return false;
  Job& job = m_jobs.emplace_back();
  job.key = Key{manifold, role};
  job.run = run;
  job.data = data;
  if (m_results.size() < m_jobs.size()) m_results.resize(m_jobs.size());
  m_indexed = false;
  if (m_streaming != nullptr && m_jobs.size() % kPublishGroup == 0) m_streaming->publish(m_jobs.size());
  return true;
}

void DeferredQueries::begin(NarrowphasePool& pool, std::size_t capacity) {
  // Reserved up front: workers read jobs and write results while add() appends.
  m_jobs.reserve(capacity);
  if (m_results.size() < capacity) m_results.resize(capacity);
  m_capacity = capacity;
  m_task = [this](std::size_t i) {
    const Job& job = m_jobs[i];
    Outcome& outcome = m_results[i];
    try {
      job.run(job.data, outcome.result);
      outcome.error = nullptr;
    } catch (...) {
      outcome.error = std::current_exception();  // an exception must not leave a worker thread
    }
    outcome.generation = m_generation;
  };
  m_streaming = &pool;
  pool.begin(m_task);
}

void DeferredQueries::finish() {
  if (m_streaming == nullptr) return;
  NarrowphasePool& pool = *m_streaming;
  m_streaming = nullptr;
  pool.close(m_jobs.size());
}

void DeferredQueries::runAll(NarrowphasePool& pool) {
  begin(pool, m_jobs.size());
  finish();
}

std::ptrdiff_t DeferredQueries::find(const Key& key) {
  if (m_cursor < m_jobs.size() && m_jobs[m_cursor].key == key) return static_cast<std::ptrdiff_t>(m_cursor);
  if (!m_indexed) {
    m_index.clear();
    for (std::size_t i = 0; i < m_jobs.size(); ++i) m_index.emplace(m_jobs[i].key, i);  // the first of a key
    m_indexed = true;
  }
  const auto found = m_index.find(key);
  return found == m_index.end() ? -1 : static_cast<std::ptrdiff_t>(found->second);
}

bool DeferredQueries::pending(const void* manifold, int role) {
  const std::ptrdiff_t i = find(Key{manifold, role});
  return i >= 0 && !m_jobs[static_cast<std::size_t>(i)].taken;
}

const RoleResult* DeferredQueries::take(const void* manifold, int role) {
  const std::ptrdiff_t i = find(Key{manifold, role});
  if (i < 0) return nullptr;
  Job& job = m_jobs[static_cast<std::size_t>(i)];
  Outcome& outcome = m_results[static_cast<std::size_t>(i)];
  if (outcome.generation != m_generation || job.taken) return nullptr;  // not computed (yet), or taken
  job.taken = true;
  m_cursor = static_cast<std::size_t>(i) + 1;
  if (outcome.error) std::rethrow_exception(outcome.error);
  return &outcome.result;
}

}  // namespace sdfccd::bullet::detail
