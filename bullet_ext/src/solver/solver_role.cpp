/// @file
/// @brief Solver mode, one role of a pair (design note Section 3.1 items 2-3; beyond the paper): the CCD
/// lists every shell point that reaches the speculative margin during the step, and each becomes a candidate
/// manifold point at the step's start, with the field's normal and Bullet's sign (distance > 0 when separated).
///
/// @details The candidate's distance d:
/// - StartsInside (phi(p0) <= margin): d = phi(p0), normal = the field's gradient at p0;
/// - Hit at fraction t (on the margin's level set at h = p0 + t (p1 - p0)): d = n . (p0 - h) + margin with n the
///   field's normal at h: the gap to the tangent plane of the surface at the first hit (exact for a plane).
/// The solver then lets the bodies close d within the step and no more (speculative contact), so nothing tunnels.
/// A turning body's point is written where and with the distance that make the solver's straight-line model of
/// the step agree with the point's arc (see the loop: the rolling sphere's support stays under its centre).
/// FirstHit is enough: only the first contact of each point matters here (AllIntervals costs the intervals).
#include "solver/solver_role.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "penalty/penalty_role.h"
#include "roles/role.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/field/polytope_fields.h"
#include "sdfccd/response/contact_normal.h"
#include "sdfccd/tolerances.h"
#include "step/contact_record.h"

namespace sdfccd::bullet::detail {
namespace {

/// The earliest fraction of the step at which a point's row is written (its lever arm turned on, its gap read):
/// a point at the bottom of its arc near the step's start is read a little later, so that gap / t stays
/// moderate (a rolling sphere measured 0.987 of 5/7 g sin theta with 0.25, 0.970 with 0.5).
constexpr double kEarliestRowFraction = 0.25;
/// cos 75 degrees: a shell point counts when its outward normal is within 75 degrees of the contact's -n.
constexpr double kGrazingCosine = 0.25881904510252074;

/// A body's motion over the step as Bullet's solver sees it: the centre's displacement and the rotation vector
/// w dt (the integrator's exact end pose comes from the same v and w).
struct BodySweep {
  Vec3 centre = Vec3::Zero();                                ///< m, world, at the step's start
  Vec3 displacement = Vec3::Zero();                          ///< m
  Eigen::Quaterniond turn = Eigen::Quaterniond::Identity();  ///< end orientation times the start's inverse
  Vec3 rotation = Vec3::Zero();                              ///< rad, w dt

  BodySweep(const Rigid& start, const Rigid& end)
      : centre(start.translation()), displacement(end.translation() - start.translation()) {
    turn = Eigen::Quaterniond(Mat3(end.linear() * start.linear().transpose())).normalized();
    const Eigen::AngleAxisd angleAxis(turn);
    rotation = angleAxis.angle() * angleAxis.axis();
  }
  /// The velocity-line displacement of the material point whose offset from the centre is `offset`.
  Vec3 lineDisplacement(const Vec3& offset) const { return displacement + rotation.cross(offset); }
  /// The offset `offsetStart` turned on to fraction t of the step.
  Vec3 offsetAt(const Vec3& offsetStart, double t) const {
    return Eigen::Quaterniond::Identity().slerp(t, turn) * offsetStart;
  }
};

/// A shell point's gap to its contact plane (normal `n`, out of the field body) over the step, to second order:
/// gap(t) = d - a t + k t^2, with a = aLine + aTurn the approach of its velocity line (the bodies' relative
/// translation, and the shell body's turn at the start's lever arm) and k the arc's curvature along n.
struct ArcGap {
  double approachLine = 0.0;  ///< m
  double approachTurn = 0.0;  ///< m
  double curvature = 0.0;     ///< m

  ArcGap(const BodySweep& shell, const BodySweep& field, const Vec3& n, const Vec3& offsetStart) {
    const Vec3 position = shell.centre + offsetStart;
    approachTurn = -n.dot(shell.rotation.cross(offsetStart));
    approachLine = -n.dot(shell.displacement - field.lineDisplacement(position - field.centre));
    curvature = 0.5 * n.dot(shell.rotation.cross(shell.rotation.cross(offsetStart)));
  }
  /// gap(t) - d.
  double change(double t) const { return t * (curvature * t - approachLine - approachTurn); }
  /// The least of gap(t) - d over [0, 1].
  double lowestChange() const {
    const double a = approachLine + approachTurn;
    if (curvature > 0.0) return change(std::clamp(a / (2.0 * curvature), 0.0, 1.0));
    return std::min(0.0, change(1.0));
  }
  /// When the turn alone brings the point nearest the plane (the bottom of a rolling body's arc), in [0, 1]; 1
  /// when the body does not turn that way.
  double turnFraction() const { return curvature > 0.0 ? std::clamp(approachTurn / (2.0 * curvature), 0.0, 1.0) : 1.0; }
};

/// The restitution Bullet's solver must get for a point that hits the field during the step, from the gap d > 0
/// it still has at the step's start, so that the rebound goes as high as one from the contact itself.
/// Bullet aims a speculative row at the normal velocity restitution - d' / dt (restitution = e times its approach
/// speed before the step's forces): e v alone would lose d' / dt, and e v from d instead of 0 would rise higher by
/// about d + e v dt / 2 (23% over e^2 h for e = 0.3 dropped from 30 cm at 1/240 s). So the target v' is the one whose
/// apex under the step's normal acceleration a (symplectic Euler: d + v' dt / 2 + v'^2 / (2 a)) is e^2 times the
/// height the point fell from over its contact, d + V^2 / (2 a) + V dt / 2 with V its approach speed before the
/// step's forces (the same integrator on the way down); with no acceleration toward the contact, v' = e V.
/// Returns what the writer adds to e; `speed`: the approach speed before the step's forces (Bullet's -rel_vel),
/// `lineApproach`: the approach over the step (after them), `dt`: the step (s).
double reboundCoefficient(double e, double gap, double solverDistance, double speed, double lineApproach, double dt) {
  if (!(speed > 0.0) || !(dt > 0.0)) return 0.0;
  const double approachSpeed = lineApproach / dt;
  const double acceleration = (approachSpeed - speed) / dt;
  double target = e * approachSpeed;
  if (acceleration > 0.0) {
    // The height the point fell from: symplectic Euler from rest reaches speed V (before this step's forces) at
    // V^2 / (2 a) + V dt / 2 below its apex.
    const double fallHeight = gap + speed * speed / (2.0 * acceleration) + 0.5 * speed * dt;
    const double apex = e * e * fallHeight;
    const double half = 0.5 * dt;
    const double discriminant = half * half - 2.0 * (gap - apex) / acceleration;
    if (discriminant >= 0.0) target = acceleration * (-half + std::sqrt(discriminant));
  }
  target = std::max(target, -solverDistance / dt);  // no lower than landing on the contact
  return std::max(0.0, (target + solverDistance / dt) / speed - e);
}

}  // namespace

template <class Field>
void computeSolverRole(const PointTree& tree, const Field& field, const SolverRoleInput& in, RoleResult& out) {
  out.margin = in.margin;
  out.ground = in.ground;
  out.candidates.clear();
  out.bounce.clear();
  out.distance.clear();
  out.hasRecord = false;
  ContactQueryResult& query = out.query;
  query.ccdSeconds = 0.0;
  // With the pair and role's history (our shell against our field) the query starts from its last front; one its
  // certificates answer alone (no contact possible) is not timed (contact_query.h, Timing).
  if (!(in.coherence && rigidCcdCertifiedClear(tree, field, in.sdfFromShellStart, in.sdfFromShellEnd, in.ccd,
                                               *in.coherence, query.ccd))) {
    double (*const clock)() = ccdClock(in.cpuClock);
    const double start = clock();
    if (in.coherence) {
      rigidCcd(tree, field, in.sdfFromShellStart, in.sdfFromShellEnd, in.ccd, *in.coherence, query.ccd);
    } else {
      rigidCcd(tree, field, in.sdfFromShellStart, in.sdfFromShellEnd, in.ccd, query.ccd);
    }
    query.ccdSeconds = clock() - start;
  }
  if (query.ccd.contacts.empty()) return;

  const PointShell& shellPoints = tree.shell();
  const double margin = in.margin;
  const BodySweep shellSweep(in.shellStart, in.shellEnd);
  const BodySweep fieldSweep(in.fieldStart, in.fieldEnd);
  // Candidate ids are unique over both roles of the pair: 2 * shell point + role (0: the shell is body 0).
  const int roleId = in.shellIsManifoldBody0 ? 0 : 1;
  ContactRecord& record = out.record;  // the contact report only: nothing for the penalty action to apply
  record = ContactRecord{};
  out.hasRecord = true;
  record.shell = in.shell;
  record.field = in.field;
  record.applied = true;
  record.firstFraction = query.ccd.firstFraction;
  for (const PointContact& c : query.ccd.contacts) {
    const Vec3& pointInShell = shellPoints.positions[static_cast<std::size_t>(c.point)];
    const Vec3 p0 = in.sdfFromShellStart * pointInShell;
    Vec3 normalInSdf;
    double distance = 0.0;
    double bounce = 0.0;
    const Vec3 p1 = in.sdfFromShellEnd * pointInShell;
    if (c.state == SegmentState::StartsInside) {
      normalInSdf = field.gradient(p0);
      distance = field.distance(p0);
    } else if (c.state == SegmentState::Hit) {
      const Vec3 hit = p0 + c.fraction * (p1 - p0);
      normalInSdf = c.fieldNormalInSdf;
      distance = normalInSdf.dot(p0 - hit) + margin;
    } else {
      continue;
    }
    double length = normalInSdf.norm();
    if (!(length > tolerance::kMinDirectionLength) || !std::isfinite(distance) || !normalInSdf.allFinite()) continue;
    {
      // The normal from the flatter of the two surfaces at the contact (contact_normal.h): a face of the shell's
      // body over an edge of the field's gives the face's normal.
      const Vec3 at = c.state == SegmentState::Hit ? Vec3(p0 + c.fraction * (p1 - p0)) : p0;
      const Vec3 gradientUnit = normalInSdf / length;
      const Vec3 shellNormalInSdf =
          in.sdfFromShellStart.linear() * shellPoints.normals[static_cast<std::size_t>(c.point)];
      const double w =
          shellNormalWeightAt(field, at, gradientUnit, shellNormalInSdf, tree.curvature(c.point), in.cellSize);
      if (w > 0.0) {
        normalInSdf = arbitratedNormal(gradientUnit, shellNormalInSdf, w);
        length = 1.0;
        if (c.state == SegmentState::Hit) distance = normalInSdf.dot(p0 - at) + margin;
      }
    }
    // How far the point's own chord over the predicted step travels towards its contact plane.
    const double approach = normalInSdf.dot(p0 - p1) / length;
    // Out of the field body, towards the shell point; Bullet's normal is on body 1, pointing to body 0.
    const Vec3 normalInWorld = in.worldFromSdfStart.linear() * (normalInSdf / length);
    // A shell point whose own surface does not face the field (its outward normal more than 75 degrees from -n)
    // grazes it: a side face beside a face it rests on, or a face point past the other body's edge, where the
    // field's gradient turns sideways (radial about the edge, and tilted further by the grid's interpolation).
    // Such points pushed stacked boxes sideways (a 10-box stack swayed and did not sleep); their neighbours on the
    // facing side carry the contact. Edges and corners (averaged normals, 45 and 55 degrees off) stay.
    const Vec3 shellNormal = in.worldFromShellStart.linear() * shellPoints.normals[static_cast<std::size_t>(c.point)];
    if (shellNormal.dot(normalInWorld) > -kGrazingCosine) continue;
    const Vec3 offsetStart = in.worldFromShellStart * pointInShell - shellSweep.centre;
    const ArcGap arc(shellSweep, fieldSweep, normalInWorld, offsetStart);
    // A separated point whose path over the predicted step never reaches its contact plane is no contact (the
    // points ahead of a rolling sphere's contact, which approach the ground by rotation and pass above it).
    // Points that do reach it (a falling body, a fast one before a thin wall) stay, so nothing tunnels; resting
    // points stay through the predicted sinking g dt^2.
    if (distance > 0.0 && std::min(distance - approach, distance + arc.lowestChange()) > 0.0) continue;
    // The row Bullet's solver gets. It holds n . (v + w x r) dt >= -d' (d' > 0), or n . (v + w x r) >= 0 and
    // pushes d' < 0 out: each point moves on the straight line of its velocity, with its impulse at the lever arm
    // r. A turning body's points move on arcs instead, and written at the step's start a rolling sphere's support
    // sits ahead of its centre, where its lines head into the ground: the solver brakes the roll and lifts the
    // sphere (a hop above v = sqrt(2 g r cos theta), 0.63 of 5/7 g sin theta over 2 s). So each point is written
    // - at fraction t of the step, when its turn alone brings it nearest the plane (the bottom of a rolling
    //   sphere's arc, where its lever arm is along n; 1 for a body that does not turn), t >= kEarliestRowFraction:
    //   its lever arm turned on to t;
    // - with d' = gap(t) / t + a: gap(t) / t the velocity change along n the point needs to be clear at t (to
    //   first order), a the approach of its line at that lever arm. A body that does not turn keeps d' = d.
    //   A penetrating point keeps d' = d (Bullet's own penetration recovery); a separated one whose path dips
    //   below the plane gets d' >= 0 (the solver holds the dip at its lever arm; recovery starts next step).
    const double fraction = std::max(kEarliestRowFraction, arc.turnFraction());
    const Vec3 offsetAtRow = shellSweep.offsetAt(offsetStart, fraction);
    const Vec3 position = shellSweep.centre + offsetAtRow;
    const double lineApproach = -normalInWorld.dot(shellSweep.lineDisplacement(offsetAtRow) -
                                                   fieldSweep.lineDisplacement(position - fieldSweep.centre));
    const double gapAtRow = fraction >= 1.0 ? distance - approach : distance + arc.change(fraction);
    const double solverDistance = distance < 0.0 ? distance : std::max(0.0, gapAtRow / fraction + lineApproach);
    if (c.state == SegmentState::Hit && distance > 0.0 && lineApproach > 0.0 && in.restitution > 0.0) {
      const Vec3 shellVelocity = in.shellVelocity.linearStart + in.shellVelocity.angularStart.cross(offsetAtRow);
      const Vec3 fieldVelocity =
          in.fieldVelocity.linearStart + in.fieldVelocity.angularStart.cross(position - fieldSweep.centre);
      const double speed = -normalInWorld.dot(shellVelocity - fieldVelocity);  // Bullet's -rel_vel (before forces)
      bounce = reboundCoefficient(in.restitution, distance, solverDistance, speed, lineApproach, in.timeStep);
    }
    ContactCandidate candidate;
    candidate.position = position;
    candidate.normal = in.shellIsManifoldBody0 ? normalInWorld : Vec3(-normalInWorld);
    // Ranked by how far the predicted line motion breaks the row (most first): the reduction keeps the least.
    candidate.distance = solverDistance - lineApproach;
    candidate.point = 2 * c.point + roleId;
    out.candidates.push_back(candidate);
    out.bounce.push_back(bounce);
    out.distance.push_back(solverDistance);
    ++record.penalty.contactCount;
    record.penalty.maxPenetration = std::max(record.penalty.maxPenetration, -distance);
  }
  record.maxPenetrationCells = record.penalty.maxPenetration / in.cellSize;
}

#define SDFCCD_SOLVER_ROLE(Field) \
  template void computeSolverRole<Field>(const PointTree&, const Field&, const SolverRoleInput&, RoleResult&);
SDFCCD_FOR_EACH_ROLE_FIELD(SDFCCD_SOLVER_ROLE)
#undef SDFCCD_SOLVER_ROLE

}  // namespace sdfccd::bullet::detail
