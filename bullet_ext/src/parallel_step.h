/// @file
/// @brief SdfccdContactSystem::runOrQueue, shared by penalty mode (sdfccd_contact_system.cpp) and solver mode
/// (solver_contacts.cpp): where one role's work runs in a planned step (sdfccd_parallel_step.cpp).
#pragma once

#include <memory>

#include "contact_step.h"
#include "deferred_queries.h"

namespace sdfccd {

inline const detail::RoleResult* SdfccdContactSystem::takePlanned(const Role& role, bool deferrableField) {
  if (m_planning || !deferrableField || !role.deferrable) return nullptr;
  const detail::RoleResult* planned = m_deferred->take(role.manifold, role.index);
  if (planned != nullptr) ++m_stats.deferredQueries;
  return planned;
}

template <class Compute>
const detail::RoleResult* SdfccdContactSystem::runOrQueue(const Role& role, bool deferrableField, Compute& compute) {
  const bool deferrable = deferrableField && role.deferrable;
  if (m_planning) {
    // The closure is copied: it holds its inputs by value (deferred_queries.h).
    if (deferrable) m_deferred->add(role.manifold, role.index, detail::DeferredQueries::Compute(compute));
    return nullptr;
  }
  if (!m_roleScratch) m_roleScratch = std::make_unique<detail::RoleResult>();
  compute(*m_roleScratch);
  return m_roleScratch.get();
}

}  // namespace sdfccd
