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
  // An override replaces the world's value of the same law; a value of another law would be combined with a
  // quantity of different units (or silently ignored by the law the pair runs), so it is refused.
  const PenaltySettings& world = m_settings.penalty;
  const bool areaLaw = world.stiffnessPerArea > 0.0;
  if (contact.stiffness && areaLaw) {
    throw Error(
        "setBodyContact: stiffness (per point) does not apply: the world's stiffness is per unit of shell "
        "area (set stiffnessPerArea)");
  }
  if (contact.stiffnessPerArea && !areaLaw) {
    throw Error("setBodyContact: stiffnessPerArea does not apply: the world's stiffness is per point (set stiffness)");
  }
  if (contact.stiffnessPerArea && !(*contact.stiffnessPerArea > 0.0)) {
    throw Error("setBodyContact: stiffnessPerArea must be > 0 (0 would be the per-point law)");
  }
  if (world.dampingRatioFromRestitution && (contact.damping || contact.dampingRatio)) {
    throw Error(
        "setBodyContact: damping does not apply: the world derives the damping ratio from the bodies' "
        "restitution (set the btRigidBody's restitution)");
  }
  const bool ratioLaw = world.dampingRatio >= 0.0;
  if (contact.damping && ratioLaw) {
    throw Error(
        "setBodyContact: damping (per point) does not apply: the world's damping is a damping ratio (set "
        "dampingRatio)");
  }
  if (contact.dampingRatio && !ratioLaw) {
    throw Error("setBodyContact: dampingRatio does not apply: the world's damping is per point (set damping)");
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
  // setBodyContact admits a ratio only where the world has an explicit one (never derived from restitution).
  p.dampingRatio = mean(pick(x.dampingRatio, p.dampingRatio), pick(y.dampingRatio, p.dampingRatio));
  return p;
}

}  // namespace sdfccd
