/// @file
/// @brief What SdfccdContactSystem records during one step (Section 4.1 and 5): each body's motion, each
/// role's penalty result and clamping, and who is shell and who field in a role. Private to sdfccd::bullet:
/// shared by the narrowphase (sdfccd_contact_system.cpp) and the response (sdfccd_contact_response.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sdfccd/bullet/sdfccd_contact_system.h"
#include "sdfccd/ccd/rigid_ccd_coherence.h"
#include "sdfccd/response/friction_anchor.h"
#include "sdfccd/response/time_of_impact_clamp.h"

class btRigidBody;

namespace sdfccd {

/// One body's frames as a penalty role's input takes them (penalty_role.h: fillPenaltyInput), for one pair of child
/// frames (the keys: the frames' addresses, which stay put through the step).
namespace detail {
struct RoleFrames {
  bool set = false;
  const Rigid* key0 = nullptr;  // the shell's child frame, or the field's child frame
  const Rigid* key1 = nullptr;  // the field's frame in its child (null for the shell)
  Rigid worldFromStart = Rigid::Identity();
  Rigid worldFromEnd = Rigid::Identity();
  Vec3 centerOfMass = Vec3::Zero();
};
}  // namespace detail

/// The motion of one collision object over the current step (motion_prediction.h).
struct SdfccdContactSystem::BodyStep {
  const btCollisionObject* object = nullptr;
  btRigidBody* body = nullptr;                   // null unless a dynamic rigid body that is awake
  bool kinematic = false;                        // infinite mass, moving
  Rigid worldFromBodyStart = Rigid::Identity();  // centre-of-mass frame
  Rigid worldFromBodyEnd = Rigid::Identity();
  BodyVelocities velocity;  // of the centre of mass, which is the body origin
  BodyInverseMass mass;     // zero unless `body`; per-area law: of the contact mass (see contactMassScale)
  /// m / m_contact <= 1: the share of a penalty impulse this body takes (contact mass scaling, per-area law).
  double contactMassScale = 1.0;
  double clampFraction = 1.0;
  bool clamped = false;
  /// The frames of this body's roles as shell and as field, computed by the first role queued in the step and kept
  /// for the roles with the same child frames (keptShellFrames, keptFieldFrames): every body takes part in many
  /// roles, each of which computed the same products. Written once, on the stepping thread, before a role that
  /// reads it is queued; never changed after.
  detail::RoleFrames shellFrames;
  detail::RoleFrames fieldFrames;

  bool finiteState = true;  // finite(), taken once when the step is made (the poses and velocities do not change)

  /// The poses' and velocities' entries all finite (Eigen's allFinite(), the same answer, in scalar code that
  /// inlines: it runs for both bodies of every pair).
  bool finite() const {
    return finiteValues(worldFromBodyStart.data(), 16) && finiteValues(worldFromBodyEnd.data(), 16) &&
           finiteValues(velocity.linearStart.data(), 3) && finiteValues(velocity.linearEnd.data(), 3) &&
           finiteValues(velocity.angularStart.data(), 3) && finiteValues(velocity.angularEnd.data(), 3);
  }
};

/// One role of one pair over the current step (SdfccdContactSystem::Record).
struct detail::ContactRecord {
  std::size_t shell = 0;  // indices into m_bodies
  std::size_t field = 0;
  PenaltyResult penalty;
  double maxPenetrationCells = 0.0;
  double firstFraction = 1.0;
  bool clamp = false;
  ClampAction action = ClampAction::None;  // Rewind or KinematicPush when clamp
  double timeStep = 0.0;                   // s
  bool applied = false;                    // SameStep: the penalty impulses are already in the velocities
  double clampFraction = 1.0;
  struct ClampPoint {
    Vec3 pointInShell = Vec3::Zero();
    Vec3 normal = Vec3::Zero();  // world, out of the field body at the point's first contact
    Vec3 point = Vec3::Zero();   // world, where the point is at the clamp fraction
  };
  std::vector<ClampPoint> clampPoints;  // the deep-entering points, earliest first (at most kMaxClampPoints)
};

namespace detail {
constexpr std::size_t kMaxClampPoints = 32;   // inelastic impact points per record
constexpr int kImpactIterations = 8;          // sequential-impulse sweeps over them
constexpr double kConvexPointsAcross = 16.0;  // convex shapes: at least this many points across their thinnest size
}  // namespace detail

/// Who is the shell and who the field in one role.
struct SdfccdContactSystem::Role {
  std::size_t shell = 0;
  std::size_t field = 0;
  const PointTree* shellTree = nullptr;  // our model's tree, or a convex shape's surface points
  Rigid bodyFromField = Rigid::Identity();
  const Rigid* modelBodyFromField = nullptr;     // the field model's own bodyFromField (lasts), when it has one
  Rigid bodyFromShellChild = Rigid::Identity();  // the shell wrapper's frame in its body (compound child)
  Rigid bodyFromFieldChild = Rigid::Identity();  // the field wrapper's frame in its body
  bool shellIsBody0 = true;
  double roleScale = 1.0;                    // s_r: 1/2 when the pair runs both roles
  double friction = 0.0;                     // mu of the pair (combined, or the settings' override)
  double dampingRatio = -1.0;                // zeta of the pair (from its restitution, or the settings')
  const PenaltySettings* penalty = nullptr;  // the pair's penalty parameters (per-body overrides combined)
  FrictionAnchorTable* anchors = nullptr;    // this pair and role's anchors, kept across steps
  RigidCcdCoherence* coherence = nullptr;    // this pair and role's CCD front, kept across steps
  const void* manifold = nullptr;            // with `index`: the key of a planned query (deferred_queries.h)
  int index = 0;                             // the role's index in its pair
  bool deferrable = false;                   // our shell against our field or a plane: may run in the batch
};

/// The friction anchors of one pair and role, kept across steps (friction_anchor.h), keyed by the pair's manifold.
struct SdfccdContactSystem::AnchorSlot {
  // The stepping thread's bookkeeping (anchorSlot(), every step while planning)...
  const btCollisionObject* shellObject = nullptr;  // a reused manifold with other objects starts afresh
  const btCollisionObject* fieldObject = nullptr;
  std::int64_t lastStep = -1;  // dropped when a step passes without its pair
  std::size_t order = 0;       // its index in the walk of step lastStep (SdfccdContactSystem::anchorSlot)
  // ...and what the role's query writes, on whichever thread runs it: on cache lines of their own, so that planning
  // does not wait for lines the other core wrote last step.
  alignas(64) FrictionAnchorTable table;
  RigidCcdCoherence coherence;  // the CCD's last front (rigid_ccd_coherence.h): exact whatever it holds
};

}  // namespace sdfccd
