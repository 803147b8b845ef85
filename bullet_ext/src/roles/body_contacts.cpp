/// @file
/// @brief BodyContacts (see body_contacts.h).
#include "roles/body_contacts.h"

#include <cmath>

#include "sdfccd/error.h"

namespace sdfccd::bullet::detail {

void BodyContacts::set(const btCollisionObject* body, const BodyContact& contact, const PenaltySettings& world) {
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
  m_contacts[body] = contact;
}

const BodyContact* BodyContacts::find(const btCollisionObject* body) const {
  const auto found = m_contacts.find(body);
  return found == m_contacts.end() ? nullptr : &found->second;
}

PenaltySettings BodyContacts::combined(const PenaltySettings& world, const btCollisionObject* a,
                                       const btCollisionObject* b) const {
  PenaltySettings p = world;
  const BodyContact* ca = m_contacts.empty() ? nullptr : find(a);
  const BodyContact* cb = m_contacts.empty() ? nullptr : find(b);
  if (ca == nullptr && cb == nullptr) return p;  // the world's settings, untouched
  static const BodyContact kNone;
  const BodyContact& x = ca != nullptr ? *ca : kNone;
  const BodyContact& y = cb != nullptr ? *cb : kNone;
  // Two springs in series, normalised so that equal stiffnesses give that stiffness.
  auto series = [](double u, double v) { return u == v ? u : (u + v > 0.0 ? 2.0 * u * v / (u + v) : 0.0); };
  auto mean = [](double u, double v) { return u == v ? u : 0.5 * (u + v); };
  auto pick = [](const std::optional<double>& v, double fallback) { return v ? *v : fallback; };
  p.stiffness = series(pick(x.stiffness, p.stiffness), pick(y.stiffness, p.stiffness));
  p.stiffnessPerArea =
      series(pick(x.stiffnessPerArea, p.stiffnessPerArea), pick(y.stiffnessPerArea, p.stiffnessPerArea));
  p.damping = mean(pick(x.damping, p.damping), pick(y.damping, p.damping));
  // setBodyContact admits a ratio only where the world has an explicit one (never derived from restitution).
  p.dampingRatio = mean(pick(x.dampingRatio, p.dampingRatio), pick(y.dampingRatio, p.dampingRatio));
  return p;
}

}  // namespace sdfccd::bullet::detail
