/// @file
/// @brief SdfccdContactSystem::obtainQuery, shared by penalty mode (sdfccd_contact_system.cpp) and solver mode
/// (solver_contacts.cpp): where one role's CCD result comes from in a planned step (sdfccd_parallel_step.cpp).
#pragma once

#include "contact_step.h"
#include "deferred_queries.h"

namespace sdfccd {

template <class Compute>
bool SdfccdContactSystem::obtainQuery(const Role& role, bool deferrableField, Compute& compute,
                                      ContactQueryResult& out) {
  const bool deferrable = deferrableField && role.deferrable;
  if (m_planning) {
    // The closure is copied: it holds its inputs by value (deferred_queries.h).
    if (deferrable) m_deferred->add(role.manifold, role.index, detail::DeferredQueries::Compute(compute));
    return false;
  }
  if (deferrable && m_deferred->take(role.manifold, role.index, out)) {
    ++m_stats.deferredQueries;
    return true;
  }
  compute(out);
  return true;
}

}  // namespace sdfccd
