/// @file
/// @brief Penalty mode, one role's work that touches no Bullet object: the query (queryContacts), the manifold
/// points, the role's record and its time-of-impact clamp (Section 4.1 and 5). It runs on the narrowphase pool in a
/// planned step (step_planner.h) or on the stepping thread; PenaltyResponder then applies it. A free function over its input, built (fillPenaltyInput) from what stays put through the step (the
/// bodies' predicted motions, the models, the settings), so nothing it reads can change under it.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <utility>
#include <vector>

#include "parallel/deferred_queries.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/response/contact_query.h"
#include "sdfccd/response/time_of_impact_clamp.h"
#include "sdfccd/shell/point_tree.h"
#include "sdfccd/thread_cpu_time.h"
#include "step/body_steps.h"
#include "step/contact_record.h"

namespace sdfccd::bullet::detail {

/// Seconds on the steady clock. The statistics' CCD and penalty times use it: reading a thread's CPU clock is a
/// system call (about 0.5 us, 7% of an 80-body pile's step when read around every query), the steady clock is not.
inline double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The clock of the CCD statistics: the thread's CPU time while the point-by-point repeat is timed beside the tree
/// (shadowLinearEvery, paper Table 4: both on the same clock), else the steady clock.
inline double (*ccdClock(bool cpuTime))() {
  return cpuTime ? &threadCpuSeconds : &steadySeconds;
}

/// What a penalty role's work reads, by value (it may run later, on the pool).
struct PenaltyRoleInput {
  ShellMotion shellMotion;
  FieldMotion fieldMotion;
  double timeStep = 0.0;
  ContactQuerySettings query;
  double cellSize = 0.0;
  double thresholdCells = 0.0;  // time-of-impact clamp threshold (cells)
  std::size_t shell = 0;        // body indices, for the record
  std::size_t field = 0;
  bool shellIsBody0 = true;        // manifold points' convention
  bool discrete = false;           // the discrete model (or a closest-point query)
  bool closestPointsOnly = false;  // report the points inside, change nothing
  bool timeOfImpactClamp = false;
  int maxManifoldPoints = 0;
  bool shellKinematic = false;
  bool fieldKinematic = false;
  bool shadowLinear = false;  // repeat the CCD point by point, timed (shadowLinearEvery)
  bool cpuClock = false;      // time the CCD on the thread's CPU clock (ccdClock)
  double roleScale = 1.0;     // passed on to the result (RoleResult)
  bool ground = false;
};

/// What a penalty role's input is built from (fillPenaltyInput): pointers to what stays put through the step, and
/// the role's own scalars.
struct PenaltyRoleFacts {
  const BodyStep* shell = nullptr;  // the bodies' motions over the step
  const BodyStep* fieldBody = nullptr;
  const Rigid* bodyFromShellChild = nullptr;  // the wrappers' frames in their bodies (compound children)
  const Rigid* bodyFromFieldChild = nullptr;
  const Rigid* bodyFromField = nullptr;      // the field's frame in its body
  const PenaltySettings* penalty = nullptr;  // the pair's penalty parameters (per-body overrides combined)
  FrictionAnchorTable* anchors = nullptr;    // this pair and role's, kept across steps (may be null)
  const RoleFrames* shellFrames = nullptr;   // the shell body's frames for bodyFromShellChild, when kept (else null)
  const RoleFrames* fieldFrames = nullptr;   // the field body's, for bodyFromFieldChild and bodyFromField
  RigidCcdCoherence* coherence = nullptr;
  std::size_t shellIndex = 0;  // body indices, for the record
  std::size_t fieldIndex = 0;
  double timeStep = 0.0;
  double cellSize = 0.0;
  double thresholdCells = 0.0;
  double roleScale = 1.0;
  double friction = 0.0;
  double dampingRatio = -1.0;
  OctreeMode octree = OctreeMode::Full;
  int maxManifoldPoints = 0;
  bool useTree = true;
  bool shellIsBody0 = true;
  bool closestPointsOnly = false;
  bool discreteModel = false;  // the settings' penalty model is the discrete one
  bool timeOfImpactClamp = false;
  bool shadowLinear = false;
  bool cpuClock = false;
  bool ground = false;
};

/// A planned penalty role as queued (~200 bytes; its input, ~1.3 KB, is built by the job on whichever thread runs
/// it: copying that much per role into memory the other core read last step stalled the planning pass).
template <class Field>
struct PenaltyRolePlan {
  const PointTree* tree = nullptr;
  HeldField<Field> field;
  PenaltyRoleFacts facts;
};

/// The identity frame that lasting frames equal to it point to (PenaltyResponder::lastingFrame): an address that
/// always holds the identity, so frames kept for it stay right whatever role asks.
inline const Rigid& identityFrame() {
  static const Rigid kIdentity = Rigid::Identity();
  return kIdentity;
}

/// A body's frames over the step for a frame fixed in it, `bodyFromFrame`: that frame at the start and end in
/// world, and the body's centre of mass in it.
inline RoleFrames bodyFramesOf(const BodyStep& body, const Rigid& bodyFromFrame) {
  RoleFrames out;
  out.worldFromStart = body.worldFromBodyStart * bodyFromFrame;
  out.worldFromEnd = body.worldFromBodyEnd * bodyFromFrame;
  out.centerOfMass = bodyFromFrame.inverse().translation();
  return out;
}

/// The shell body's frames for its child frame `bodyFromChild` (a compound's child; the identity else): its
/// points' frame.
inline RoleFrames shellFramesOf(const BodyStep& shell, const Rigid& bodyFromChild) {
  return bodyFramesOf(shell, bodyFromChild);
}

/// The field body's: its field's frame.
inline RoleFrames fieldFramesOf(const BodyStep& fieldBody, const Rigid& bodyFromChild, const Rigid& childFromField) {
  return bodyFramesOf(fieldBody, Rigid(bodyFromChild * childFromField));
}

/// The body's kept shell frames for `bodyFromChild` (by address: give only frames whose value never changes, the
/// identityFrame or a model's frame): computed by the first role of the step that asks, then returned to the roles
/// that ask with the same frame; null for another frame (its role computes its own). Stepping thread only (see
/// BodyStep::shellFrames).
inline const RoleFrames* keptShellFrames(BodyStep& shell, const Rigid* bodyFromChild) {
  RoleFrames& kept = shell.shellFrames;
  if (!kept.set) {
    kept = shellFramesOf(shell, *bodyFromChild);
    kept.key0 = bodyFromChild;
    kept.set = true;
  }
  return kept.key0 == bodyFromChild ? &kept : nullptr;
}

/// The same for the field body's frames, keyed by both frames' addresses.
inline const RoleFrames* keptFieldFrames(BodyStep& fieldBody, const Rigid* bodyFromChild, const Rigid* childFromField) {
  RoleFrames& kept = fieldBody.fieldFrames;
  if (!kept.set) {
    kept = fieldFramesOf(fieldBody, *bodyFromChild, *childFromField);
    kept.key0 = bodyFromChild;
    kept.key1 = childFromField;
    kept.set = true;
  }
  return kept.key0 == bodyFromChild && kept.key1 == childFromField ? &kept : nullptr;
}

/// A body's motion over the step from its frames (a closest-point query: the start pose throughout), into the
/// members of a ShellMotion or a FieldMotion.
inline void setMotion(const BodyStep& body, const RoleFrames& frames, bool closestPointsOnly, Rigid& worldFromStart,
               Rigid& worldFromEnd, Vec3& centerOfMass, BodyVelocities& velocity, BodyInverseMass& mass) {
  worldFromStart = frames.worldFromStart;
  worldFromEnd = closestPointsOnly ? worldFromStart : frames.worldFromEnd;
  centerOfMass = frames.centerOfMass;
  velocity = body.velocity;
  mass = body.mass;
}

/// The shell's motion (setMotion).
inline void setShellMotion(const BodyStep& shell, const RoleFrames& frames, bool closestPointsOnly, ShellMotion& out) {
  setMotion(shell, frames, closestPointsOnly, out.worldFromShellStart, out.worldFromShellEnd, out.centerOfMassInShell,
            out.velocity, out.mass);
}

/// The field body's motion (setMotion).
inline void setFieldMotion(const BodyStep& fieldBody, const RoleFrames& frames, bool closestPointsOnly, FieldMotion& out) {
  setMotion(fieldBody, frames, closestPointsOnly, out.worldFromSdfStart, out.worldFromSdfEnd, out.centerOfMassInSdf,
            out.velocity, out.mass);
}

/// The role's input from its facts (the frames as queryContacts wants them: see contact_query.h). Every write here
/// is unconditional and the same for every role: the parallel batch reuses one input per thread
/// (PenaltyResponder::queue), whose other fields must keep their defaults.
inline void fillPenaltyInput(const PenaltyRoleFacts& f, PenaltyRoleInput& in) {
  const BodyStep& shell = *f.shell;
  const BodyStep& fieldBody = *f.fieldBody;
  in.discrete = f.closestPointsOnly || f.discreteModel;
  // The frame contract of queryContacts (contact_query.h): the shell's points live in its body frame (whose
  // origin is the centre of mass); the field's frame sits at bodyFromField in its body. A closest-point query
  // looks at the current poses: nothing moves.
  // A compound child's frame sits at bodyFromChild in its body; handles go from the body's centre of mass.
  // The frames: kept ones (the same expressions, computed once per body and step) or this role's own (built only
  // then: a default RoleFrames per role, two identity transforms, cost a tenth of this function).
  if (f.shellFrames != nullptr) {
    setShellMotion(shell, *f.shellFrames, f.closestPointsOnly, in.shellMotion);
  } else {
    setShellMotion(shell, shellFramesOf(shell, *f.bodyFromShellChild), f.closestPointsOnly, in.shellMotion);
  }
  if (f.fieldFrames != nullptr) {
    setFieldMotion(fieldBody, *f.fieldFrames, f.closestPointsOnly, in.fieldMotion);
  } else {
    setFieldMotion(fieldBody, fieldFramesOf(fieldBody, *f.bodyFromFieldChild, *f.bodyFromField), f.closestPointsOnly,
                   in.fieldMotion);
  }

  ContactQuerySettings& query = in.query;
  query.penalty = *f.penalty;
  if (in.discrete) query.penalty.model = PenaltyModel::Discrete;
  query.penalty.roleScale = f.roleScale;
  query.penalty.friction = f.friction;
  query.penalty.dampingRatio = f.dampingRatio;
  query.cellSize = f.cellSize;
  query.arbitrateNormals = true;  // the normal from the flatter surface (contact_normal.h)
  query.anchors = f.anchors;
  query.coherence = f.coherence;
  query.discreteMode = CcdMode::AllIntervals;  // every contact at the end pose
  query.octree = f.octree;
  query.useTree = f.useTree;
  query.threads = 1;
  query.integratePenalty = !f.closestPointsOnly;
  in.timeStep = f.timeStep;
  in.cellSize = f.cellSize;
  in.thresholdCells = f.thresholdCells;
  in.shell = f.shellIndex;
  in.field = f.fieldIndex;
  in.shellIsBody0 = f.shellIsBody0;
  in.closestPointsOnly = f.closestPointsOnly;
  in.timeOfImpactClamp = f.timeOfImpactClamp;
  in.maxManifoldPoints = f.maxManifoldPoints;
  in.shellKinematic = shell.kinematic;
  in.fieldKinematic = fieldBody.kinematic;
  in.shadowLinear = f.shadowLinear;
  in.cpuClock = f.cpuClock;
  in.roleScale = f.roleScale;
  in.ground = f.ground;
}

/// The role's work into `out` (see the file comment).
template <class Field>
void computePenaltyRole(const PointTree& tree, const Field& field, const PenaltyRoleInput& in, RoleResult& out) {
  ContactQueryClocks clocks;
  clocks.ccd = ccdClock(in.cpuClock);
  clocks.penalty = &steadySeconds;
  // The query in this thread's own result (its buffers warm from the thread's last query); `out` gets its summary.
  thread_local ContactQueryResult query;
  queryContacts(tree, field, in.shellMotion, in.fieldMotion, in.timeStep, in.query, query, clocks);
  out.roleScale = in.roleScale;
  out.ground = in.ground;
  out.shadowSeconds = 0.0;
  out.hasRecord = false;
  out.penalty.ccdSeconds = query.ccdSeconds;
  out.penalty.penaltySeconds = query.penaltySeconds;
  out.penalty.segmentQueries = query.ccd.stats.segmentQueries;
  out.penalty.touched = !query.ccd.contacts.empty();
  out.penalty.coefficients = query.coefficients;
  if (!out.manifoldPoints.empty()) out.manifoldPoints.clear();  // (its size lives on the result's third line)
  const RigidCcdResult& ccdResult = query.ccd;
  const Rigid& sdfFromShellStart = query.sdfFromShellStart;
  const Rigid& sdfFromShellEnd = query.sdfFromShellEnd;
  if (in.shadowLinear) {
    RigidCcdSettings linear;
    linear.sigma = in.query.penalty.sigma;
    linear.mode = in.discrete ? in.query.discreteMode : CcdMode::AllIntervals;
    linear.octree = in.query.octree;
    linear.useTree = false;
    linear.threads = 1;
    thread_local RigidCcdResult shadow;
    const double shadowStart = threadCpuSeconds();
    rigidCcd(tree, field, in.discrete ? sdfFromShellEnd : sdfFromShellStart, sdfFromShellEnd, linear, shadow);
    out.shadowSeconds = threadCpuSeconds() - shadowStart;
  }
  if (ccdResult.contacts.empty()) return;

  const PointShell& shellPoints = tree.shell();
  const Rigid& worldFromShellEnd = in.shellMotion.worldFromShellEnd;
  const Rigid& worldFromFieldStart = in.fieldMotion.worldFromSdfStart;
  const Rigid& worldFromFieldEnd = in.fieldMotion.worldFromSdfEnd;
  // Manifold points: the deepest points at the step's end, for users (the solver ignores them).
  if (in.maxManifoldPoints > 0) {
    std::vector<std::pair<double, int>> deepest;
    for (int i = 0; i < static_cast<int>(ccdResult.contacts.size()); ++i) {
      if (ccdResult.contacts[static_cast<std::size_t>(i)].depthAtEnd < 0.0) {
        deepest.emplace_back(ccdResult.contacts[static_cast<std::size_t>(i)].depthAtEnd, i);
      }
    }
    const std::size_t keep = std::min(deepest.size(), static_cast<std::size_t>(in.maxManifoldPoints));
    std::partial_sort(deepest.begin(), deepest.begin() + static_cast<std::ptrdiff_t>(keep), deepest.end());
    for (std::size_t k = 0; k < keep; ++k) {
      const PointContact& c = ccdResult.contacts[static_cast<std::size_t>(deepest[k].second)];
      const Vec3& pointInShell = shellPoints.positions[static_cast<std::size_t>(c.point)];
      const Vec3 pointInWorld = worldFromShellEnd * pointInShell;
      Vec3 gradientInWorld = worldFromFieldEnd.linear() * field.gradient(sdfFromShellEnd * pointInShell);
      if (!(gradientInWorld.norm() > 0.0)) continue;
      gradientInWorld.normalize();
      const double depth = c.depthAtEnd;
      if (in.shellIsBody0) {
        // B is the field: its outward normal points towards A; the point on B is on the field's surface.
        out.manifoldPoints.push_back({gradientInWorld, Vec3(pointInWorld - gradientInWorld * depth), depth});
      } else {
        // B is the shell: its point is on B, and B's normal towards A is minus A's field gradient.
        out.manifoldPoints.push_back({Vec3(-gradientInWorld), pointInWorld, depth});
      }
    }
  }
  if (in.closestPointsOnly) return;

  ContactRecord& record = out.record;
  record = ContactRecord{};
  out.hasRecord = true;
  record.shell = in.shell;
  record.field = in.field;
  record.penalty = query.penalty;
  record.maxPenetrationCells = record.penalty.maxPenetration / in.cellSize;
  record.firstFraction = ccdResult.firstFraction;
  record.timeStep = in.timeStep;
  if (in.discrete || !in.timeOfImpactClamp) return;
  // A point that entered during the step and went deeper than the threshold (at an interval's middle, or at the
  // end) would be stopped too late by forces that act one step later: clamp at its first hit.
  const double threshold = in.thresholdCells * in.cellSize;
  std::vector<std::pair<double, ContactRecord::ClampPoint>> entering;
  for (const PointContact& c : ccdResult.contacts) {
    if (c.state != SegmentState::Hit || !(c.fraction > 0.0) || c.intervals.empty()) continue;
    const Vec3& pointInShell = shellPoints.positions[static_cast<std::size_t>(c.point)];
    const Vec3 p0 = sdfFromShellStart * pointInShell;
    const Vec3 p1 = sdfFromShellEnd * pointInShell;
    double deepestDepth = c.depthAtEnd;
    for (std::size_t i = 0; i < c.intervals.size(); ++i) {
      const double t = 0.5 * (c.intervals[i].begin + c.intervals[i].end);
      deepestDepth = std::min(deepestDepth, field.distance(p0 + t * (p1 - p0)) - in.query.penalty.sigma);
    }
    if (!(deepestDepth < -threshold)) continue;
    ContactRecord::ClampPoint clampPoint;
    clampPoint.pointInShell = pointInShell;
    clampPoint.normal = (worldFromFieldStart.linear() * c.fieldNormalInSdf).normalized();
    if (!clampPoint.normal.allFinite()) continue;
    entering.emplace_back(c.fraction, clampPoint);
  }
  if (!entering.empty()) {
    std::stable_sort(entering.begin(), entering.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    if (entering.size() > kMaxClampPoints) entering.resize(kMaxClampPoints);
    record.clamp = true;
    record.clampFraction = entering.front().first;
    record.action = clampAction(true, in.shellKinematic, in.fieldKinematic);
    for (auto& e : entering) {
      const Vec3 startInWorld = in.shellMotion.worldFromShellStart * e.second.pointInShell;
      e.second.point = startInWorld +
                       record.clampFraction * (in.shellMotion.worldFromShellEnd * e.second.pointInShell - startInWorld);
      record.clampPoints.push_back(e.second);
    }
  }
  if (record.clamp && record.action == ClampAction::Rewind) {
    // The bodies go back to the clamp fraction: report the penetration there, not along the discarded path.
    double deepestDepth = 0.0;
    for (const PointContact& c : ccdResult.contacts) {
      const Vec3& pointInShell = shellPoints.positions[static_cast<std::size_t>(c.point)];
      const Vec3 p0 = sdfFromShellStart * pointInShell;
      const Vec3 p1 = sdfFromShellEnd * pointInShell;
      deepestDepth =
          std::max(deepestDepth, -(field.distance(p0 + record.clampFraction * (p1 - p0)) - in.query.penalty.sigma));
    }
    record.maxPenetrationCells = deepestDepth / in.cellSize;
    record.penalty.maxPenetration = deepestDepth;
  }
}

}  // namespace sdfccd::bullet::detail
