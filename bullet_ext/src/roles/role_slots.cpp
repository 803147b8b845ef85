/// @file
/// @brief RoleSlots (see role_slots.h).
#include "roles/role_slots.h"

#include <iterator>

namespace sdfccd::bullet::detail {
namespace {
/// Steps between two walks over the slots that drop the stale ones.
constexpr std::int64_t kSlotEvictionPeriod = 64;
}  // namespace

RoleSlot& RoleSlots::slot(const btPersistentManifold* manifold, int role, const btCollisionObject* shell,
                          const btCollisionObject* field, std::int64_t step) {
  // Bullet walks its pairs in the same order step after step, so the slot after the last one found is tried first
  // (a hashed lookup misses the cache three times; an 80-body pile looks up ~2,000 slots per step).
  const Key key{manifold, role};
  RoleSlot* slot = nullptr;
  // Written field by field in place: a Visit{...} temporary is copied with `rep movs`, slow to start.
  const auto recordVisit = [&] {
    Visit& visit = m_order.emplace_back();
    visit.key = key;
    visit.slot = slot;
    visit.shellObject = shell;
    visit.fieldObject = field;
    visit.step = step;
  };
  if (m_cursor < m_lastOrder.size() && m_lastOrder[m_cursor].key == key) {
    const Visit& last = m_lastOrder[m_cursor];
    slot = last.slot;
    if (last.step + 1 == step && last.shellObject == shell && last.fieldObject == field) {
      // Met at this place of last step's walk, with the same objects: it keeps its table and history. Decided from
      // the walk's own (sequential) record: the slot is only written here, and its cache line is often cold.
      ++m_cursor;
      slot->lastStep = step;
      slot->order = m_order.size();
      recordVisit();
#if defined(__GNUC__)
      // The next lookup's slot, most likely: its bookkeeping line is written then, and is cold (a role's work
      // in between touches other memory). A hint only: a wrong guess costs one load.
      if (m_cursor < m_lastOrder.size()) __builtin_prefetch(m_lastOrder[m_cursor].slot, 1);
#endif
      return *slot;
    }
  } else {
    std::unique_ptr<RoleSlot>& owned = m_slots[key];
    if (!owned) owned = std::make_unique<RoleSlot>();
    slot = owned.get();
  }
  if (slot->lastStep + 1 >= step && slot->order < m_lastOrder.size() && m_lastOrder[slot->order].slot == slot) {
    m_cursor = slot->order + 1;  // found where last step's walk had it: go on from there
  }
  if (slot->shellObject != shell || slot->fieldObject != field || slot->lastStep + 1 < step) {
    slot->table.clear();  // another pair reuses the manifold, or the pair was not dispatched (asleep)
    slot->coherence.reset();
    slot->shellObject = shell;
    slot->fieldObject = field;
  }
  if (slot->lastStep != step) {  // this step's walk, for the next step's guesses
    slot->lastStep = step;
    slot->order = m_order.size();
    recordVisit();
  }
  return *slot;
}

void RoleSlots::endStep(std::int64_t step) {
  m_lastOrder.swap(m_order);
  m_order.clear();
  m_cursor = 0;
  // Slots whose pair was not processed last step are dropped now and then: one that comes back first resets
  // (slot()), so when they go changes no result, and walking every slot each step costs as much as a query.
  if (step % kSlotEvictionPeriod == 0) {
    for (auto it = m_slots.begin(); it != m_slots.end();) {
      it = it->second->lastStep + 1 < step ? m_slots.erase(it) : std::next(it);
    }
  }
}

}  // namespace sdfccd::bullet::detail
