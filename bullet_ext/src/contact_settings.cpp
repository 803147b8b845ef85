/// @file
/// @brief validateContactSettings: the checks a ContactSystem's settings pass (contact_settings.h).
#include <cmath>
#include <string>

#include "sdfccd/error.h"
#include "step/contact_step.h"

namespace sdfccd::bullet::detail {

void validateContactSettings(const ContactSettings& settings) {
  const PenaltySettings& p = settings.penalty;
  if (!(p.friction >= 0.0) || !std::isfinite(p.friction) || !(p.frictionSlipSpeed > 0.0)) {
    throw Error("contact settings: friction must be finite and >= 0, frictionSlipSpeed > 0");
  }
  if (!(p.stiffness >= 0.0) || !std::isfinite(p.stiffness) || !(p.damping >= 0.0) || !std::isfinite(p.damping) ||
      p.subintervals < 1) {
    throw Error("contact settings: stiffness and damping must be finite and >= 0, subintervals >= 1");
  }
  if (!(p.stiffnessPerArea >= 0.0) || !std::isfinite(p.stiffnessPerArea)) {
    throw Error("contact settings: stiffnessPerArea (contact.stiffness_per_area) must be finite and >= 0");
  }
  if (!(p.dampingRatio <= 2.0) || !std::isfinite(p.dampingRatio)) {
    throw Error("contact settings: dampingRatio (contact.damping_ratio) must be in [0, 2]");
  }
  p.caps.validate();
  if (!(settings.toiDepthCells >= 0.0) || !std::isfinite(settings.toiDepthCells)) {
    throw Error("contact settings: toiDepthCells must be finite and >= 0");
  }
  if (!(settings.convexPointSpacingCells > 0.0) || !std::isfinite(settings.convexPointSpacingCells) ||
      settings.convexMaxPoints < 12) {
    throw Error("contact settings: convexPointSpacingCells must be positive and finite, convexMaxPoints >= 12");
  }
  if (settings.maxManifoldPoints < 0 || settings.maxManifoldPoints > 4) {
    throw Error("contact settings: maxManifoldPoints must be in 0..4");
  }
  if (!(settings.speculativeMarginCells > 0.0) || !std::isfinite(settings.speculativeMarginCells) ||
      !(settings.maxSpeculativeMargin > 0.0) || !std::isfinite(settings.maxSpeculativeMargin)) {
    throw Error("contact settings: speculativeMarginCells and maxSpeculativeMargin must be positive and finite");
  }
  if (settings.mode == SdfccdContactMode::Solver && p.model == PenaltyModel::Discrete) {
    throw Error("contact settings: contact.model discrete applies to penalty mode only (contact.mode is solver)");
  }
  if (settings.threads < 0 || settings.threads > kMaxNarrowphaseThreads)
    throw Error("contact settings: threads must be in 0.." + std::to_string(kMaxNarrowphaseThreads) +
                " (0: all hardware threads)");
}

}  // namespace sdfccd::bullet::detail
