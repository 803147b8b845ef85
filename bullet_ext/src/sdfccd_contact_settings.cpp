/// @file
/// @brief SdfccdContactSystem's settings (validation; the narrowphase pool follows `threads`) and its registration
/// with a dispatcher (see sdfccd_contact_system.h). Split from sdfccd_contact_system.cpp, which keeps the
/// narrowphase.
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btEmptyCollisionAlgorithm.h>

#include <cmath>
#include <memory>

#include "bullet_shape_fields.h"
#include "narrowphase_pool.h"
#include "sdfccd/bullet/sdfccd_collision_algorithm.h"
#include "sdfccd/bullet/sdfccd_contact_system.h"
#include "sdfccd/error.h"

namespace sdfccd {

void SdfccdContactSystem::setSettings(const SdfccdContactSettings& settings) {
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
  // The pool starts with the first planned step that has queries (planStep): a world that never steps starts none.
  if (m_pool && m_pool->threads() != detail::resolveThreads(settings.threads)) m_pool.reset();
  m_settings = settings;
}

void SdfccdContactSystem::registerWith(btCollisionDispatcher& dispatcher) {
  m_createFuncs.clear();
  m_createFuncs.push_back(std::make_unique<SdfccdCollisionAlgorithm::CreateFunc>(this, false));
  m_createFuncs.push_back(std::make_unique<SdfccdCollisionAlgorithm::CreateFunc>(this, true));
  m_createFuncs.push_back(std::make_unique<btEmptyAlgorithm::CreateFunc>());
  btCollisionAlgorithmCreateFunc* contacts = m_createFuncs[0].get();
  btCollisionAlgorithmCreateFunc* closest = m_createFuncs[1].get();
  btCollisionAlgorithmCreateFunc* empty = m_createFuncs[2].get();
  // Ours against every type but compounds (Bullet's compound algorithms dispatch their children back here)
  // and btEmptyShape: processPair decides, and announces what it cannot handle (bullet_shape_fields.h).
  detail::registerOurPairs(dispatcher, CUSTOM_CONCAVE_SHAPE_TYPE, contacts, closest, empty);
}

}  // namespace sdfccd
