/// @file
/// @brief RoleSlots: what one role of one pair keeps across steps (its friction anchors and its CCD history), keyed by
/// the pair's manifold and the role's index, and the order in which the step's walk meets them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include "sdfccd/ccd/rigid_ccd_coherence.h"
#include "sdfccd/response/friction_anchor.h"

class btCollisionObject;
class btPersistentManifold;

namespace sdfccd::bullet::detail {

/// The friction anchors (design 2.4) and CCD front of one pair and role, kept across steps.
struct RoleSlot {
  // The stepping thread's bookkeeping (RoleSlots::slot, every step while planning)...
  const btCollisionObject* shellObject = nullptr;  // a reused manifold with other objects starts afresh
  const btCollisionObject* fieldObject = nullptr;
  std::int64_t lastStep = -1;  // dropped when a step passes without its pair
  std::size_t order = 0;       // its index in the walk of step lastStep (RoleSlots::slot)
  // ...and what the role's query writes, on whichever thread runs it: on cache lines of their own, so that planning
  // does not wait for lines the other core wrote last step.
  alignas(64) FrictionAnchorTable table;
  RigidCcdCoherence coherence;  // the CCD's last front (rigid_ccd_coherence.h): exact whatever it holds
};

class RoleSlots {
 public:
  /// The slot of (manifold, role) in step `step`, created on first use; it forgets table and history when another
  /// pair reuses the manifold, or when a step passed without its pair (asleep).
  RoleSlot& slot(const btPersistentManifold* manifold, int role, const btCollisionObject* shell,
                 const btCollisionObject* field, std::int64_t step);
  /// After the step's response (`step`: the number of the next step): this step's walk guides the next step's
  /// lookups, and now and then the slots whose pair was not processed go.
  void endStep(std::int64_t step);

 private:
  using Key = std::pair<const btPersistentManifold*, int>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      return std::hash<const void*>()(k.first) ^ (static_cast<std::size_t>(k.second) * 0x9e3779b97f4a7c15ull);
    }
  };
  struct Visit {  // one slot met in a step's walk: its key, slot, objects and step
    Key key;
    RoleSlot* slot;
    const btCollisionObject* shellObject;
    const btCollisionObject* fieldObject;
    std::int64_t step;
  };
  // The slots (an 80-body pile has ~2,000), and the order in which this and the last step's walk met them.
  std::unordered_map<Key, std::unique_ptr<RoleSlot>, KeyHash> m_slots;
  std::vector<Visit> m_order, m_lastOrder;
  std::size_t m_cursor = 0;
};

}  // namespace sdfccd::bullet::detail
