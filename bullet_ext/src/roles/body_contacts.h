/// @file
/// @brief BodyContacts: the per-body penalty overrides a user sets (BodyContact, contact_settings.h) and a pair's
/// combination of them with the world's settings.
#pragma once

#include <unordered_map>

#include "sdfccd/bullet/contact_settings.h"
#include "sdfccd/response/penalty_model.h"

class btCollisionObject;

namespace sdfccd::bullet::detail {

class BodyContacts {
 public:
  /// Throws sdfccd::Error on a null body, bad values, or a value of another law than the world's (`world`).
  void set(const btCollisionObject* body, const BodyContact& contact, const PenaltySettings& world);
  void clear(const btCollisionObject* body) { m_contacts.erase(body); }
  /// The body's override, or null.
  const BodyContact* find(const btCollisionObject* body) const;
  bool empty() const { return m_contacts.empty(); }
  /// The world's penalty settings with the two bodies' overrides combined.
  PenaltySettings combined(const PenaltySettings& world, const btCollisionObject* a, const btCollisionObject* b) const;

 private:
  std::unordered_map<const btCollisionObject*, BodyContact> m_contacts;
};

}  // namespace sdfccd::bullet::detail
