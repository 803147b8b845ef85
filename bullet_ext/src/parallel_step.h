/// @file
/// @brief SdfccdContactSystem::takePlanned, shared by penalty mode (sdfccd_contact_system.cpp) and solver mode
/// (solver_contacts.cpp), and runOrQueue, solver mode's (penalty mode queues a smaller plan: queuePenaltyRole): where
/// one role's work runs in a planned step (sdfccd_parallel_step.cpp).
#pragma once

#include <memory>
#include <type_traits>

#include "contact_step.h"
#include "deferred_queries.h"

namespace sdfccd {

inline const detail::RoleResult* SdfccdContactSystem::takePlanned(const Role& role, bool deferrableField) {
  if (m_planning || !deferrableField || !role.deferrable) return nullptr;
  const detail::RoleResult* planned = m_deferred->take(role.manifold, role.index);
  if (planned != nullptr) ++m_stats.deferredQueries;
  return planned;
}

template <class Input, class Run>
const detail::RoleResult* SdfccdContactSystem::runOrQueue(const Role& role, bool deferrableField, const Input& input,
                                                          Run run) {
  static_assert(std::is_empty_v<Run>, "runOrQueue: `run` must capture nothing (its inputs are in `input`)");
  if (m_planning) {
    if (deferrableField && role.deferrable) {
      // The inputs are stashed for the step (deferred_queries.h): the closure holds a pointer, no copy.
      const Input& kept = m_deferred->stash(input);
      // A refused query (the batch full: not with two roles per planned pair) is computed when Bullet reaches it;
      // its pair is then not applied as a whole (processPair's fast path).
      if (!m_deferred->add(role.manifold, role.index, [&kept, run](detail::RoleResult& out) { run(kept, out); }))
        m_planIncomplete.push_back(role.manifold);
    }
    return nullptr;
  }
  if (!m_roleScratch) m_roleScratch = std::make_unique<detail::RoleResult>();
  run(input, *m_roleScratch);
  return m_roleScratch.get();
}

}  // namespace sdfccd
