/// @file
/// @brief GodObject: constraint-based 6-DoF haptic rendering with continuous collision detection
/// (paper Section 4.2, after Ortega et al. [10]).
///
/// @details A quasi-static "god object" (zero velocity at all times) carries the manipulated point shell and
/// stays on the surface of the static object (a distance field). One simulation cycle, given the device pose
/// x_h and the god-object pose x_s:
///   1. a_u = k_s (x_h - x_s)                                    (eq. 6; 6-D pose difference, world axes)
///   2. one row J_k = [n_k^T, (r_k x n_k)^T] per contact k        (eq. 7; n_k = -grad(phi)/|grad(phi)|, the
///      static object's normal pointing into it; r_k from the god-object's centre to the point)
///   3. a_c = argmin ||a - a_u||_M subject to J a <= 0            (contact_qp.h; with qp.friction > 0, Coulomb
///      friction on a linearised pyramid: the quasi-static Stewart-Trinkle LCP, contact_qp.h)
///   4. the tentative pose: one symplectic Euler step from rest with a unit cycle time, i.e. the
///      displacement a_c (quasi-static: k_s is the fraction of the gap closed per cycle), optionally scaled
///      down so that one cycle moves at most maxStepTranslation / maxStepRotation (scaling keeps J a <= 0)
///   5. continuous collision detection of the shell from x_s to the tentative pose (FirstHit leaves), with
///      the points in contact in the last cycle ignored (the paper's sliding remedy); the god-object moves
///      only to the earliest contact fraction t_c
///   6. the contact set for the next cycle: the points the CCD reported plus the previously ignored points,
///      checked discretely at the new pose: phi - sigma <= contactThreshold keeps them
///   7. F_c = k_h M (a_c - a_u), rendered to the device.
///
/// The constraints are linear in the motion, but a rotating body's points follow chords that sink by
/// ~ r theta^2 / 2 per cycle at active contacts (and so does sliding over concave curvature). Two additions
/// keep that from accumulating: maxStepRotation bounds theta per cycle, and depthCorrection adds an outward
/// lift to the constrained move for contacts that drifted below sigma (after the QP: the cone of the QP is
/// unchanged, and a user pressing into the contact cannot cancel the lift, as a bias of a_u would be
/// projected away; without it, a point held at slideFloor freezes every move that sinks it to second order,
/// e.g. sliding along the inside of a bent tube).
///
/// Two details beyond the paper, both switchable:
/// - sigma > 0 (a small fraction of a voxel) keeps the god-object a hair off the surface, so the discrete
///   re-check of step 6 sees the contacts it just made and rounding never puts a point below phi = 0.
/// - guardIgnoredPoints: the ignored points get their own CCD at the lower level set slideFloor (<= sigma),
///   so a sliding point that runs into a concave corner (where the QP's first-order constraint does not see
///   the other wall), or sinks through the second-order effects of curvature and rotation, is stopped there
///   instead of being re-checked only after it went through. A point already under the floor (by rounding)
///   is held at its own depth (less sinkTolerance): without that, it would be free to sink once under.
///
/// The discrete variant (continuous = false; paper Fig. 11) skips step 5: it moves to the tentative pose
/// and takes as contacts every point with phi - sigma <= contactThreshold there.
///
/// Clearance cache (clearanceCache, on by default; the results are bit-identical with it off): step 5 skips
/// every point that provably cannot reach sigma during the move. Per point it keeps the clearance
/// phi - sigma where it was last evaluated and the body's travel since then, bounded by the sum over cycles
/// of |translation of the centre| + |rotation angle| * |point - centre| (a bound on every point's chord). With
/// the field's gradient bound L (field_culling_bounds.h; a GridField holds it), phi anywhere on the point's later
/// segments stays above clearance - L * travel (the path from the evaluation point to any later position runs inside
/// the field's box, which is convex, where L holds; outside the box the segment query sees no contact). Grid fields use
/// the bound of the point's neighbourhood instead (local_lipschitz_bounds.h: about 1 near a smooth wall where the
/// global bound is sqrt(3)), valid for a travel up to its reach, after which the point is re-evaluated. Points whose
/// bound runs out are re-evaluated at the start of the move (one trilinear lookup) and queried by CCD only if the move
/// itself can use up their clearance. The cycle then costs O(points) cheap tests, and segment queries only for the
/// points near the surface that move towards it; without it, a body resting in a tight fit (the peg fully inserted:
/// every side point within 0.07 voxel of the wall) re-queries every point near the wall every cycle although the
/// god-object barely moves.
///
/// Grid fields also split the travel per axis of the field (axis_lipschitz_bounds.h): a point's evaluation records
/// its clearance, its block of per-axis gradient bounds G and the travel sums then, per axis T_a (sum over cycles of
/// |translation of the centre along a|) and R (sum of rotation angles). Its position then moved by d with
/// |d_a| <= dT_a + |rotation part|_a, so phi changed by at most sum_a G_a dT_a + |G| dR |point - centre| along the
/// straight path, which stays within the block's reach while sum_a dT_a + dR |point - centre| does. A point whose
/// scalar budget ran out is kept skipped while that bound stays below its clearance: sliding along an axis-aligned
/// wall (G along it ~0: the peg in its hole) does not use the clearance up.
///
/// Contacts: steps 5 and 6 (and the discrete variant's candidates) gather from every obstacle of the god-object's
/// contact source (ObstacleContacts, haptic_obstacles.h), the rows in the same form: the scene's one static field is
/// an obstacle with a fixed pose, and keeps the clearance cache; with several obstacles a cycle whose time
/// (setObstacleTime) moved an obstacle starts with its push.
///
/// Frames: the shell frame is the god-object's body frame and its origin is the centre of mass.
/// Thread safety: one GodObject per simulation thread; the trees and fields are only read.
#pragma once

#include <cstdint>
#include <vector>

#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/haptics/contact_qp.h"
#include "sdfccd/haptics/haptic_obstacles.h"
#include "sdfccd/haptics/rigid_body_state.h"  // poses and twists of the god-object
#include "sdfccd/haptics/spatial_types.h"
#include "sdfccd/math_types.h"

namespace sdfccd::haptics {

/// Settings of the constraint-based renderer.
struct GodObjectSettings {
  double couplingGain = 0.5;                    ///< k_s of eq. (6) (per cycle; the paper uses 0.5)
  double renderStiffness = 300.0;               ///< N/m: k_h M (a_c - a_u) with k_h = renderStiffness / (k_s mass)
  double mass = 0.1;                            ///< kg, the god-object's mass (the QP's metric)
  Vec3 inertiaDiagonal = Vec3::Constant(1e-4);  ///< kg m^2, body axes
  double sigma = 0.0;                           ///< contact level set (model units), >= 0
  double contactThreshold = 0.0;                ///< model units: a point with phi - sigma <= this is in contact
  double slideFloor = 0.0;                      ///< level set of the ignored points' guard CCD (model units, <= sigma)
  double sinkTolerance = 0.0;                   ///< model units: how much deeper an ignored point already under the
                                                ///< floor may go in one cycle (0: not at all)
  bool ignoreContactPoints = true;              ///< the paper's sliding remedy (off only to show why it is needed)
  bool guardIgnoredPoints = true;               ///< run the guard CCD on the ignored points
  double maxStepTranslation = 0.0;              ///< model units per cycle (0: unlimited)
  double maxStepRotation = 0.01;                ///< rad per cycle (0: unlimited); keeps point paths near-linear
  double depthCorrection = 1.0;                 ///< gain of the outward bias for contacts below sigma (0: off)
  bool continuous = true;                       ///< false: the discrete-collision variant (Fig. 11)
  bool clearanceCache = true;                   ///< skip points that provably cannot reach sigma (see @details)
  bool axisCertificates = true;                 ///< grid fields: the cache also splits the travel per axis
  OctreeMode octree = OctreeMode::Leaves;       ///< cell skipping at haptic rates (Section 4.1: leaves)
  CcdMethod ccdMethod = CcdMethod::Exact;
  int threads = 1;       ///< CCD worker threads
  ContactQpSettings qp;  ///< includes the Coulomb friction coefficient qp.friction (0: frictionless, the NNLS)
};

/// One contact of the god-object.
struct GodObjectContact {
  int point = -1;                          ///< shell point index (of the obstacle's shell when that is the shell)
  int obstacle = -1;                       ///< the obstacle's index in the contact source (ObstacleContacts)
  Vec3 normalIntoObstacle = Vec3::Zero();  ///< n_k, world, unit
  Vec3 handle = Vec3::Zero();              ///< r_k, world (from the centre to the point)
  double distance = 0.0;                   ///< phi at the point (model units)
};

/// What one simulation cycle did.
struct GodObjectStepResult {
  ContactQpState qpState = ContactQpState::Solved;
  bool blocked = false;                ///< the QP's optimum was ~0 although a_u was not
  Vec6 unconstrained = Vec6::Zero();   ///< a_u
  Vec6 constrained = Vec6::Zero();     ///< a_c
  Vec6 wrenchOnDevice = Vec6::Zero();  ///< F_c (N, N m)
  double fraction = 1.0;               ///< how much of the tentative move was made (t_c)
  int contactCount = 0;                ///< contacts used by the QP this cycle
  int nextContactCount = 0;            ///< contacts after the move (used next cycle)
  int newContacts = 0;                 ///< of those, points that were not in contact before
  double minContactDistance = 0.0;     ///< smallest phi over the next contact set (model units)
  std::int64_t segmentQueries = 0;     ///< CCD work
  /// Moving obstacles (haptic_obstacles.h): no push clears them all (the tool is pinched between obstacles closing
  /// in); the god-object stayed where it was before the push.
  bool squeezed = false;
};
/// The god-object of one manipulated shell against the obstacles of its contact source.
class GodObject {
 public:
  /// `contacts`: the obstacles, the tool's shell among them (one static field at a fixed pose, or several, static or
  /// moving); the god-object owns it. Throws sdfccd::Error on bad settings, a non-finite pose, or friction against a
  /// moving obstacle.
  GodObject(ObstacleContacts contacts, const Rigid& worldFromGodStart, const GodObjectSettings& settings);

  /// The time (s) the obstacles are at during the next cycles: a cycle whose time moved an obstacle first pushes
  /// the god-object out of its way (haptic_obstacles.h).
  void setObstacleTime(double time) { m_obstacleTime = time; }

  /// One simulation cycle towards the device pose.
  GodObjectStepResult step(const Rigid& worldFromDevice);

  const Rigid& pose() const { return m_pose; }  ///< worldFromGod
  const std::vector<GodObjectContact>& contacts() const { return m_contacts; }
  const GodObjectSettings& settings() const { return m_settings; }
  /// The deepest penetration (phi < 0) of any obstacle pair at the god-object's pose (model units, >= 0).
  double penetration() { return m_obstacles.penetration(m_pose); }

 private:
  /// Moving obstacles: moves them to m_obstacleTime and pushes the god-object out of their way.
  void pushByObstacles(GodObjectStepResult& out);
  /// Depth correction: the outward lift of the contacts that drifted below sigma (see @details).
  Vec3 depthCorrection() const;
  /// Step 3: the contact QP, with friction when settings.qp.friction > 0 (contact_qp.h); fills m_qpResult.
  void solveContacts(const Mat6& mass, const Vec6& request);
  /// Step 4: the tentative move a_c + lift, limited per cycle.
  Vec6 limitedMove(const Vec3& lift) const;
  /// Step 6: the contact set at the new pose.
  void updateContacts(GodObjectStepResult& out);

  ObstacleContacts m_obstacles;
  double m_obstacleTime = 0.0;  // s
  Rigid m_pose;
  GodObjectSettings m_settings;
  std::vector<GodObjectContact> m_contacts;
  std::vector<GodObjectContact> m_next;
  ConstraintRows m_rows;
  ContactQpSolver m_qp;
  ContactQpResult m_qpResult;
  std::vector<Vec3> m_normals;  // solveContacts with friction: n_k and r_k of the contacts
  std::vector<Vec3> m_handles;
  std::vector<Vec3> m_patchNormals;  // the same reduced to their patches' hulls (reduceContactPatches)
  std::vector<Vec3> m_patchHandles;
};

}  // namespace sdfccd::haptics
