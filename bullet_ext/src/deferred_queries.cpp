/// @file
/// @brief DeferredQueries (see deferred_queries.h).
#include "deferred_queries.h"

#include <utility>

#include "narrowphase_pool.h"

namespace sdfccd::detail {

void DeferredQueries::clear() {
  m_jobs.clear();
  m_index.clear();
  m_indexed = false;
  m_cursor = 0;
}

void DeferredQueries::add(const void* manifold, int role, Compute compute) {
  Job job;
  job.key = Key{manifold, role};
  job.compute = std::move(compute);
  m_jobs.push_back(std::move(job));
  if (m_results.size() < m_jobs.size()) m_results.resize(m_jobs.size());
  m_indexed = false;
}

void DeferredQueries::runAll(NarrowphasePool& pool) {
  pool.run(m_jobs.size(), [this](std::size_t i) {
    try {
      m_jobs[i].compute(m_results[i]);
    } catch (...) {
      m_jobs[i].error = std::current_exception();  // an exception must not leave a worker thread
    }
    m_jobs[i].done = true;
  });
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
  if (!job.done || job.taken) return nullptr;
  job.taken = true;
  m_cursor = static_cast<std::size_t>(i) + 1;
  if (job.error) std::rethrow_exception(job.error);
  return &m_results[static_cast<std::size_t>(i)];
}

}  // namespace sdfccd::detail
