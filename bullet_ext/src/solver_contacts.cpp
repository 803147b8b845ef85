/// @file
/// @brief Solver mode, one role of a pair (issue 13 design note, Section 3.1 items 2-3; beyond the paper): the CCD
/// lists every shell point that reaches the speculative margin during the step, and each becomes a candidate
/// manifold point at the step's start, with the field's normal and Bullet's sign (distance > 0 when separated).
///
/// @details The candidate's distance d:
/// - StartsInside (phi(p0) <= margin): d = phi(p0), normal = the field's gradient at p0;
/// - Hit at fraction t (on the margin's level set at h = p0 + t (p1 - p0)): d = n . (p0 - h) + margin with n the
///   field's normal at h: the gap to the tangent plane of the surface at the first hit (exact for a plane).
/// The solver then lets the bodies close d within the step and no more (speculative contact), so nothing tunnels.
/// FirstHit is enough: only the first contact of each point matters here (AllIntervals costs the intervals).
#include <algorithm>
#include <cmath>

#include "contact_step.h"
#include "sdfccd/bullet/sdfccd_contact_system.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/thread_cpu_time.h"
#include "sdfccd/tolerances.h"

namespace sdfccd {

template <class Field>
void SdfccdContactSystem::collectSolverCandidates(const Role& role, const Field& field, double cellSize,
                                                  bool shellIsManifoldBody0) {
  const BodyStep& shell = m_bodies[role.shell];
  const BodyStep& fieldBody = m_bodies[role.field];
  const PointTree& tree = *role.shellTree;
  const PointShell& shellPoints = tree.shell();
  const double margin = std::min(m_settings.speculativeMarginCells * cellSize, m_settings.maxSpeculativeMargin);
  m_candidateMargin = std::max(m_candidateMargin, margin);
  const Rigid worldFromSdfStart = fieldBody.worldFromBodyStart * role.bodyFromField;
  const Rigid worldFromSdfEnd = fieldBody.worldFromBodyEnd * role.bodyFromField;
  const Rigid sdfFromShellStart = worldFromSdfStart.inverse() * shell.worldFromBodyStart;
  const Rigid sdfFromShellEnd = worldFromSdfEnd.inverse() * shell.worldFromBodyEnd;

  RigidCcdSettings ccd;
  ccd.sigma = margin;
  ccd.mode = CcdMode::FirstHit;
  ccd.octree = m_settings.octree;
  ccd.useTree = m_settings.useTree;
  ccd.threads = 1;
  const double start = threadCpuSeconds();
  rigidCcd(tree, field, sdfFromShellStart, sdfFromShellEnd, ccd, m_solverCcd);
  const double seconds = threadCpuSeconds() - start;
  m_stats.ccdSeconds += seconds;
  if constexpr (std::is_same_v<Field, PlaneField>) {
    m_stats.groundCcdSeconds += seconds;
    ++m_stats.groundCcdQueries;
  }
  ++m_stats.ccdQueries;
  m_stats.segmentQueries += m_solverCcd.stats.segmentQueries;
  if (m_solverCcd.contacts.empty()) return;

  // Candidate ids are unique over both roles of the pair: 2 * shell point + role (0: the shell is body 0).
  const int roleId = shellIsManifoldBody0 ? 0 : 1;
  Record record;  // the contact report only: nothing for the penalty action to apply
  record.shell = role.shell;
  record.field = role.field;
  record.applied = true;
  record.firstFraction = m_solverCcd.firstFraction;
  for (const PointContact& c : m_solverCcd.contacts) {
    const Vec3& pointInShell = shellPoints.positions[static_cast<std::size_t>(c.point)];
    const Vec3 p0 = sdfFromShellStart * pointInShell;
    Vec3 normalInSdf;
    double distance = 0.0;
    double bounce = 0.0;
    const Vec3 p1 = sdfFromShellEnd * pointInShell;
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
    const double length = normalInSdf.norm();
    if (!(length > tolerance::kMinDirectionLength) || !std::isfinite(distance) || !normalInSdf.allFinite()) continue;
    // How far the point's own chord over the predicted step travels towards its contact plane.
    const double approach = normalInSdf.dot(p0 - p1) / length;
    // A separated point whose chord does not reach its contact plane within the step is no contact: Bullet's
    // solver would still act on it wherever its instantaneous velocity closes the gap d in dt (a "ghost" contact:
    // the points ahead of a rolling sphere's contact approach the ground by rotation but never reach it, and
    // pushing them brakes the roll and lifts the sphere). Points that do reach it (a falling body, a fast one
    // before a thin wall) stay, so nothing tunnels; resting points stay through the predicted sinking g dt^2.
    if (distance > 0.0 && !(approach >= distance)) continue;
    // Bullet's solver aims a speculative point at the velocity restitution - d / dt: a bounce would lose d / dt.
    // The writer adds d / (approach dt) to the restitution of such a point, so the rebound is e v.
    if (c.state == SegmentState::Hit && distance > 0.0 && approach > 0.0) bounce = distance / approach;
    // Out of the field body, towards the shell point; Bullet's normal is on body 1, pointing to body 0.
    const Vec3 normalInWorld = worldFromSdfStart.linear() * (normalInSdf / length);
    ContactCandidate candidate;
    candidate.position = shell.worldFromBodyStart * pointInShell;
    candidate.normal = shellIsManifoldBody0 ? normalInWorld : Vec3(-normalInWorld);
    candidate.distance = distance;
    candidate.point = 2 * c.point + roleId;
    m_candidates.push_back(candidate);
    m_candidateBounce.push_back(bounce);
    ++record.penalty.contactCount;
    record.penalty.maxPenetration = std::max(record.penalty.maxPenetration, -distance);
  }
  record.maxPenetrationCells = record.penalty.maxPenetration / cellSize;
  m_records.push_back(record);
}

template void SdfccdContactSystem::collectSolverCandidates<GridField>(const Role&, const GridField&, double, bool);
template void SdfccdContactSystem::collectSolverCandidates<PlaneField>(const Role&, const PlaneField&, double, bool);
template void SdfccdContactSystem::collectSolverCandidates<BoxField>(const Role&, const BoxField&, double, bool);
template void SdfccdContactSystem::collectSolverCandidates<SphereField>(const Role&, const SphereField&, double, bool);
template void SdfccdContactSystem::collectSolverCandidates<CapsuleField>(const Role&, const CapsuleField&, double,
                                                                         bool);

}  // namespace sdfccd
