/// @file
/// @brief Per-body penalty parameters of SdfccdContactSystem (SdfccdBodyContact, sdfccd_contact_system.h): the
/// overrides a user sets per body and the pair's combination of them with the world's settings.
#include <cmath>

#include "sdfccd/bullet/sdfccd_contact_system.h"
#include "sdfccd/error.h"

namespace sdfccd {

void SdfccdContactSystem::setBodyContact(const btCollisionObject* body, const SdfccdBodyContact& contact) {
  if (body == nullptr) throw Error("setBodyContact: the body is null");
  auto nonNegative = [](const std::optional<double>& v) { return !v || (*v >= 0.0 && std::isfinite(*v)); };
  if (!nonNegative(contact.stiffness) || !nonNegative(contact.stiffnessPerArea) || !nonNegative(contact.damping)) {
    throw Error("setBodyContact: stiffness, stiffnessPerArea and damping must be finite and >= 0");
  }
  if (contact.dampingRatio && !(*contact.dampingRatio >= 0.0 && *contact.dampingRatio <= 2.0)) {
    throw Error("setBodyContact: dampingRatio must be in [0, 2]");
  }
  m_bodyContacts[body] = contact;
}

void SdfccdContactSystem::clearBodyContact(const btCollisionObject* body) {
  m_bodyContacts.erase(body);
}

const SdfccdBodyContact* SdfccdContactSystem::bodyContact(const btCollisionObject* body) const {
  const auto found = m_bodyContacts.find(body);
  return found == m_bodyContacts.end() ? nullptr : &found->second;
}

PenaltySettings SdfccdContactSystem::combinedPenalty(const btCollisionObject* a, const btCollisionObject* b) const {
  PenaltySettings p = m_settings.penalty;
  const SdfccdBodyContact* ca = m_bodyContacts.empty() ? nullptr : bodyContact(a);
  const SdfccdBodyContact* cb = m_bodyContacts.empty() ? nullptr : bodyContact(b);
  if (ca == nullptr && cb == nullptr) return p;  // the world's settings, untouched
  static const SdfccdBodyContact kNone;
  const SdfccdBodyContact& x = ca != nullptr ? *ca : kNone;
  const SdfccdBodyContact& y = cb != nullptr ? *cb : kNone;
  // Two springs in series, normalised so that equal stiffnesses give that stiffness.
  auto series = [](double u, double v) { return u == v ? u : (u + v > 0.0 ? 2.0 * u * v / (u + v) : 0.0); };
  auto mean = [](double u, double v) { return u == v ? u : 0.5 * (u + v); };
  auto pick = [](const std::optional<double>& v, double world) { return v ? *v : world; };
  p.stiffness = series(pick(x.stiffness, p.stiffness), pick(y.stiffness, p.stiffness));
  p.stiffnessPerArea =
      series(pick(x.stiffnessPerArea, p.stiffnessPerArea), pick(y.stiffnessPerArea, p.stiffnessPerArea));
  p.damping = mean(pick(x.damping, p.damping), pick(y.damping, p.damping));
  if (x.dampingRatio || y.dampingRatio) {
    const double world = p.dampingRatio >= 0.0 ? p.dampingRatio : 0.0;
    p.dampingRatio = mean(pick(x.dampingRatio, world), pick(y.dampingRatio, world));
    p.dampingRatioFromRestitution = false;  // an explicit ratio replaces the restitution-derived one
  }
  return p;
}

}  // namespace sdfccd
