/// @file
/// @brief What a ContactSystem (contact_system.h) is set up with and what it reports: the world's contact settings,
/// one body's penalty overrides, one role's contact report and the cumulative statistics.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "sdfccd/ccd/segment_ccd.h"
#include "sdfccd/math_types.h"
#include "sdfccd/response/contact_mode.h"
#include "sdfccd/response/force_timing.h"
#include "sdfccd/response/penalty_model.h"

class btCollisionObject;

namespace sdfccd::bullet {

/// Receives one line of text: an unsupported pair's announcement (ContactSystem::setLogCallback).
using LogCallback = std::function<void(const std::string& line)>;

/// The most narrowphase threads a contact system accepts (ContactSettings::threads, `--threads`).
inline constexpr int kMaxNarrowphaseThreads = 1024;

/// Settings of the contact model, shared by every pair of one world.
struct ContactSettings {
  /// Penalty (the paper's model) or Solver (speculative manifold points answered by Bullet's solver; see
  /// bullet_ext/src/solver/solver_role.cpp). Solver by default: on the 20-bunny drop it has the larger stable step
  /// at a lower cost (`sdfccd bench bullet --part modes,stable`, docs/benchmarks.md).
  SdfccdContactMode mode = SdfccdContactMode::Solver;
  /// Solver mode: CCD level set and speculative reach, in cells of the field, capped at maxSpeculativeMargin.
  double speculativeMarginCells = 0.5;
  double maxSpeculativeMargin = 0.002;              ///< m (model units)
  ForceTiming forceTiming = ForceTiming::SameStep;  ///< see ForceTiming
  /// Model (continuous/discrete), stiffness per area (or per point), damping ratio (or per point), direction,
  /// friction law; new worlds get PenaltySettings::trustworthy().
  PenaltySettings penalty = PenaltySettings::trustworthy();
  bool timeOfImpactClamp = true;         ///< continuous model only: clamp bodies at first hits (contact_system.h)
  double toiDepthCells = 0.5;            ///< clamp when an entering point ends deeper than this (field cells)
  bool useTree = true;                   ///< point tree (true) or point by point (the linear baseline)
  bool coherentCcd = true;               ///< tree: start each pair and role's query from its last front (same contacts)
  OctreeMode octree = OctreeMode::Full;  ///< cell skipping in grid fields
  int maxManifoldPoints = 4;             ///< manifold points reported per pair (0..4)
  /// Bullet convex shapes (box, sphere, capsule) against our field: the spacing of the points sampled on
  /// their surface, in cells of the field they meet, and at most 1/16 of the shape's thinnest size (beyond
  /// the paper; see ContactSystem).
  double convexPointSpacingCells = 1.0;
  int convexMaxPoints = 20000;  ///< cap on the points sampled on one convex shape
  /// Narrowphase threads: the CCD of the step's pairs of our shapes (and of ours against ground planes), both
  /// roles, runs on a persistent pool of this many threads (bullet_ext/src/step/step_planner.cpp); 0: the
  /// machine's hardware threads; 1: on the stepping thread. Results are bit-identical for every value. The pool's
  /// threads (this many minus the stepping thread) start at the first step with queries and stay parked between
  /// steps until the system goes.
  int threads = 0;
};

/// One body's penalty parameters (penalty mode), overriding the world's ContactSettings::penalty; an unset
/// field keeps the world's value. A pair combines its two bodies' values (a body without an override brings the
/// world's): stiffnesses like two springs in series, normalised so that equal values give that value
/// (2 a b / (a + b)); damping ratios and per-point damping by their mean. A pair where neither body has an
/// override uses the world's settings unchanged. The shell's density is the model's (BodyModelSettings::points).
/// An override must be of the world's law (setBodyContact refuses the others with one line): `stiffnessPerArea`
/// in a per-area world (the default), `stiffness` in a per-point one; `dampingRatio` where the world has an
/// explicit ratio, `damping` where it has per-point damping; where the world derives the ratio from restitution
/// (the default), a body's damping is its btRigidBody's restitution, combined the Bullet way.
struct BodyContact {
  std::optional<double> stiffness;         ///< N/m per point (PenaltySettings::stiffness), >= 0
  std::optional<double> stiffnessPerArea;  ///< N/m^3 (PenaltySettings::stiffnessPerArea; 0: per-point law), >= 0
  std::optional<double> damping;           ///< N s/m per point (PenaltySettings::damping), >= 0
  std::optional<double> dampingRatio;      ///< zeta in [0, 2] (PenaltySettings::dampingRatio)
};

/// One (shell body, field body) role of a pair over the last step: the contact report.
struct PairContact {
  const btCollisionObject* shellObject = nullptr;
  const btCollisionObject* fieldObject = nullptr;
  int contactCount = 0;               ///< shell points that produced a force
  double maxPenetration = 0.0;        ///< model units
  double maxPenetrationCells = 0.0;   ///< in cells of the field (a plane: of the shell body's field)
  Vec3 forceOnShell = Vec3::Zero();   ///< eq. (5) average over the step (N), world
  Vec3 torqueOnShell = Vec3::Zero();  ///< N m, about the shell body's centre of mass
  Vec3 forceOnField = Vec3::Zero();   ///< N
  Vec3 torqueOnField = Vec3::Zero();  ///< N m
  bool clamped = false;               ///< the pair triggered time-of-impact clamping
  double firstFraction = 1.0;         ///< earliest first hit of the step (fraction)
};

/// Counters, cumulative since construction.
struct ContactStatistics {
  /// Time of the rigid CCD queries (s), all fields, summed over the threads that ran them: steady-clock time
  /// (a thread CPU clock read is a system call, dearer than most queries a pile's certificates answer), or thread
  /// CPU time while the benchmarks time a point-by-point repeat beside it (paper Table 4). A query the CCD
  /// history answers with no traversal is not timed.
  double ccdSeconds = 0.0;
  double groundCcdSeconds = 0.0;      ///< the part of ccdSeconds spent against static planes (s)
  double shadowLinearSeconds = 0.0;   ///< the benchmarks' point-by-point repeats, between bodies only (s)
  std::int64_t shadowSteps = 0;       ///< steps in which the repeats ran
  double penaltySeconds = 0.0;        ///< wall time integrating the penalty model (s)
  std::int64_t ccdQueries = 0;        ///< rigid CCD queries (two per body pair and step)
  std::int64_t segmentQueries = 0;    ///< segment queries inside them
  std::int64_t clamps = 0;            ///< bodies moved back to a time of impact
  std::int64_t kinematicPushes = 0;   ///< clamps against a kinematic body (no rewind; design 2.5)
  std::int64_t softenedPairs = 0;     ///< roles whose stiffness the omega dt cap softened (design 2.2)
  std::int64_t unsupportedPairs = 0;  ///< pairs Bullet dispatched that we do not handle (no contact)
  /// Pairs skipped because a body's pose, velocity or motion was NaN or infinite: such a body
  /// gets no contact, so nothing non-finite reaches the other body (SceneWorld rejects it before the step).
  std::int64_t nonFinitePairs = 0;
  double maxPenetrationCells = 0.0;  ///< largest penetration seen (cells)
  // Work counters: what each effect cost (zero when a scene does not ask for the effect).
  std::int64_t groundCcdQueries = 0;     ///< rigid CCD queries against static planes (the "ground" effect)
  std::int64_t penaltySamples = 0;       ///< penalty force samples in contact (PenaltyResult::samples)
  std::int64_t dampingEvaluations = 0;   ///< of them, with the damping term ("damping")
  std::int64_t torqueEvaluations = 0;    ///< of them, with torques ("rotation")
  std::int64_t frictionEvaluations = 0;  ///< of them, with friction ("friction")
  /// Pairs that ran no CCD because neither body moves: each sleeping, static, or kinematic at zero velocity
  /// (their manifolds keep last step's points for Bullet's island manager).
  std::int64_t restingPairs = 0;
  std::int64_t deferredQueries = 0;  ///< of ccdQueries, those computed in a step's parallel batch
  double parallelWallSeconds = 0.0;  ///< wall time of the parallel batches (s)
};

}  // namespace sdfccd::bullet
