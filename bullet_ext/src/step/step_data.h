/// @file
/// @brief StepData: what the stages of a Bullet step share (the settings, the step's bodies and records, the planned
/// queries, the statistics). ContactStep owns it; the role enumeration, the responders and the planner read and
/// write it, on the stepping thread.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "parallel/deferred_queries.h"
#include "roles/body_contacts.h"
#include "roles/role.h"
#include "sdfccd/bullet/contact_settings.h"
#include "step/body_steps.h"
#include "step/contact_loads.h"
#include "step/contact_record.h"

namespace sdfccd::bullet::detail {

struct StepData {
  ContactSettings settings;
  /// Benchmarks (SceneWorldSettings::shadowLinearEvery): every n-th step (n > 0) each query is repeated point by point (useTree = false),
  /// result discarded, and timed into ContactStatistics::shadowLinearSeconds (paper Table 4: linear vs tree on the
  /// very same motion). 0: off.
  int shadowLinearEvery = 0;
  ContactStatistics stats;
  std::int64_t stepCounter = 0;
  BodySteps bodies;
  ContactLoads loads;
  BodyContacts bodyContacts;
  std::vector<ContactRecord> records;
  DeferredQueries deferred;  // the step's planned queries (step_planner.h)
  std::vector<const void*> planIncomplete;  // manifolds with a role the batch refused (none expected)
  std::unique_ptr<RoleResult> roleScratch;  // a role computed on the stepping thread (keeps buffers)

  /// The role's result from this step's parallel batch, or null (not planned).
  const RoleResult* takePlanned(const Role& role, bool deferrableField) {
    if (!deferrableField || !role.deferrable) return nullptr;
    const RoleResult* planned = deferred.take(role.manifold, role.index);
    if (planned != nullptr) ++stats.deferredQueries;
    return planned;
  }
  /// The result a role computed on the stepping thread is written into.
  RoleResult& scratch() {
    if (!roleScratch) roleScratch = std::make_unique<RoleResult>();
    return *roleScratch;
  }
  /// Every shadowLinearEvery-th step repeats the queries point by point.
  bool shadowStep() const { return shadowLinearEvery > 0 && stepCounter % shadowLinearEvery == 0; }
};

}  // namespace sdfccd::bullet::detail
