/// @file
/// @brief queryContacts(): one shell body against one field body over one step — the rigid CCD (paper
/// Section 3.3) and the penalty integrals (Section 4.1, eqs. 3-5) on one frame contract, the core call that the
/// Bullet plugin and the haptic penalty renderer share.
///
/// @details Frames: the caller gives the shell's motion in the frame of its points (worldFromShellStart ->
/// worldFromShellEnd) and the field's in the field's frame (worldFromSdfStart -> worldFromSdfEnd), both in
/// world (penalty_model.h: ShellMotion, FieldMotion). The call forms, once,
///   sdfFromShellStart = worldFromSdfStart^-1 * worldFromShellStart,
///   sdfFromShellEnd   = worldFromSdfEnd^-1   * worldFromShellEnd,
/// runs the CCD on them (each shell point on the segment sdfFromShellStart * x -> sdfFromShellEnd * x) and
/// integrates the penalty model over the contacts it found, on the same motions; the result holds both, the
/// penalty's impulses already split between the shell body and the field body (world, about each body's
/// centre of mass), and the two transforms, for what the caller computes next (manifold points,
/// time-of-impact clamping, contact stiffness).
///
/// What the CCD computes is the caller's choice, not unified here:
/// - PenaltyModel::Continuous: the CCD over the step's motion, every contact sub-interval (AllIntervals).
/// - PenaltyModel::Discrete: the CCD at the end pose only (start = end: it lists the points inside there) in
///   `discreteMode`: Bullet asks for AllIntervals, the haptic renderer for FirstHit (the first hit is all a
///   zero-length motion can have).
/// - `integratePenalty = false`: the CCD only (a closest-point query at the current poses: give equal start and
///   end poses and the discrete model).
/// The penalty model runs only when the CCD found a contact (PenaltyResult stays zero otherwise), after the
/// settings are checked. With the per-area law (PenaltySettings::stiffnessPerArea > 0) the shell's point areas
/// give k_i, and the pair's caps and damping ratio (perAreaCoefficients) are applied before integrating.
///
/// Timing: the core keeps no clock. A caller that times the two phases passes its clocks (ContactQueryClocks);
/// they are called once before and once after each phase, never inside the traversal. A CCD answered by the
/// coherence history's certificates alone (rigidCcdCertifiedClear: no traversal, no contact) is not timed.
///
/// Thread safety: as rigidCcd(): the tree and the field are read-only; one result per thread.
#pragma once

#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/math_types.h"
#include "sdfccd/response/penalty_model.h"
#include "sdfccd/shell/point_tree.h"

namespace sdfccd {

/// Settings of one contact query.
struct ContactQuerySettings {
  PenaltySettings penalty;  ///< the penalty model; its `model` picks the CCD's motion and `sigma` is the CCD's too
  CcdMode discreteMode = CcdMode::AllIntervals;  ///< what the discrete model's CCD computes (see the file comment)
  CcdMethod method = CcdMethod::Exact;           ///< root finding per cell (leaves)
  OctreeMode octree = OctreeMode::Full;          ///< cell skipping in grid fields
  bool useTree = true;                           ///< false: point by point (the linear baseline)
  int threads = 1;                               ///< CCD worker threads (0: all cores)
  bool integratePenalty = true;                  ///< false: the CCD only
  double cellSize = 0.0;                         ///< the field's cell (model units): the Blend direction's band
  /// Each contact's force direction from the flatter of the two surfaces (contact_normal.h): for a pair of two
  /// bodies with shells, whose other role sees the mirror contact.
  bool arbitrateNormals = false;
  /// io: this pair and role's friction anchors, kept by the caller across steps (FrictionModel::Anchor); null:
  /// no anchor friction (the regularized law is used instead).
  FrictionAnchorTable* anchors = nullptr;
  /// io: this pair and role's CCD history, kept by the caller across steps (rigid_ccd_coherence.h); null: the
  /// fresh query. The contacts are the same either way.
  RigidCcdCoherence* coherence = nullptr;
};

/// Optional clocks of the two phases (seconds; any monotonic clock, e.g. thread CPU time). Null: not timed.
struct ContactQueryClocks {
  double (*ccd)() = nullptr;      ///< read around the CCD
  double (*penalty)() = nullptr;  ///< read around the penalty integrals
};

/// What one contact query found.
struct ContactQueryResult {
  Rigid sdfFromShellStart = Rigid::Identity();  ///< the shell's frame in the field's at the step's start
  Rigid sdfFromShellEnd = Rigid::Identity();    ///< and at its end (the discrete CCD ran at this pose only)
  RigidCcdResult ccd;                           ///< every contact, sorted by point index
  PenaltyResult penalty;                        ///< zero unless penaltyIntegrated
  PairResponseCoefficients coefficients;        ///< per-area law: the caps' result for this role (penalty_model.h)
  bool penaltyIntegrated = false;               ///< the penalty model ran (asked for, and the CCD found contacts)
  double ccdSeconds = 0.0;                      ///< by ContactQueryClocks::ccd (0 without it)
  double penaltySeconds = 0.0;                  ///< by ContactQueryClocks::penalty (0 without it)
};

/// The query (see the file comment). `Field` is one of the field types of field_interface.h. `outResult` is
/// overwritten; reusing one across calls keeps the CCD's buffers. `timestep` (s) must be positive and finite
/// when the penalty model runs. Throws sdfccd::Error as rigidCcd() and integratePenalty() do.
template <class Field>
void queryContacts(const PointTree& shellTree, const Field& field, const ShellMotion& shell,
                   const FieldMotion& fieldBody, double timestep, const ContactQuerySettings& settings,
                   ContactQueryResult& outResult, const ContactQueryClocks& clocks = {});

}  // namespace sdfccd
