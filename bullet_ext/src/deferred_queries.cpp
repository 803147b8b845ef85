/// @file
/// @brief DeferredQueries (see deferred_queries.h).
#include "deferred_queries.h"

#include <utility>

#include "narrowphase_pool.h"

namespace sdfccd::detail {

void DeferredQueries::clear() {
  m_jobs.clear();
  m_index.clear();
}

void DeferredQueries::add(const void* manifold, int role, Compute compute) {
  const auto inserted = m_index.emplace(Key{manifold, role}, m_jobs.size());
  if (!inserted.second) return;  // planned already (a pair seen twice in one plan): the first one counts
  Job job;
  job.compute = std::move(compute);
  m_jobs.push_back(std::move(job));
  if (m_results.size() < m_jobs.size()) m_results.resize(m_jobs.size());
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

bool DeferredQueries::take(const void* manifold, int role, ContactQueryResult& out) {
  const auto found = m_index.find(Key{manifold, role});
  if (found == m_index.end()) return false;
  Job& job = m_jobs[found->second];
  if (!job.done || job.taken) return false;
  job.taken = true;
  if (job.error) std::rethrow_exception(job.error);
  std::swap(out, m_results[found->second]);
  return true;
}

}  // namespace sdfccd::detail
