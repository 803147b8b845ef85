/// @file
/// @brief ContactSystem: the continuous penalty contact of Section 4.1 inside Bullet's step, with time-of-impact
/// clamping against tunnelling. One object per world: constructing it installs the contact, destroying it removes
/// it.
///
/// @details Where each part runs in btDiscreteDynamicsWorld's step:
/// 1. Narrowphase (our collision algorithm, then the pair's stages:
///    bullet_ext/src/step/contact_step.cpp): for each pair, each body in each role (shell of
///    A vs field of B, then shell of B vs field of A; a btStaticPlaneShape is an analytic PlaneField and only
///    a field; a btBoxShape, btSphereShape or btCapsuleShape is an analytic field and points sampled on its
///    surface, so it takes both roles like ours, and so does any other btConvexShape; a triangle mesh or
///    terrain is its triangles near our body as a field and its vertices there as points),
///    the rigid CCD runs over the step's motion: start = the
///    body's current transform, end = its motion integrated over the step from the velocity *plus* the forces
///    Bullet will add (gravity and applied forces, the same symplectic Euler step integrateVelocities/
///    integrateTransforms perform), which is the actual end of the step because our contacts add no solver
///    rows. (getInterpolationWorldTransform at this point omits gravity: it is off by g dt^2.) The continuous
///    penalty model integrates impulse and angular impulse over the contact sub-intervals (eqs. 3-4) — or the
///    discrete model at the end pose. Both run in one core call, queryContacts (contact_query.h), on the
///    frames of the shell's body and of the field (the model's field frame in its body).
/// 2. The impulses I and M reach the velocities as impulses (eq. 5: the averaged force F* = I/dt acting over
///    a step is the impulse F* dt; forces applied with applyCentralForce would accumulate over substeps
///    until clearForces). When, is a setting (ForceTiming): the paper's "over the next step" (in
///    updateAction: this object is a btActionInterface, run after integrateTransforms), or at once in the
///    narrowphase, before Bullet integrates the same step (the default: stable at stiffer settings).
/// 3. Time-of-impact clamping (beyond the paper): averaged penalty forces act one step late and cannot stop a
///    fast body at a thin wall. When a shell point *entered* the contact set during the step (state Hit) and
///    either left it again before the step's end (it passed through) or ends deeper than
///    toiDepthCells cells, the pair "clamps": every dynamic body of the pair is moved back to its pose at the
///    earliest such first-hit fraction (translation lerped, rotation slerped along the step's motion), an
///    inelastic impulse at the first-contact point removes the approaching normal velocity, and the pair's
///    penalty impulses of that step are dropped. Resting and sliding contact (points that start inside, or
///    shallow entries) are left to the penalty forces. Only the continuous model clamps: the discrete model
///    is the baseline and may tunnel.
/// Contacts are visible to users as manifold points (at most 4 per pair, the deepest at the step's end,
/// normal on B, negative distance) and through lastStepContacts(). The solver never answers them twice: our
/// manifolds get a contact processing threshold of -BT_LARGE_FLOAT, and Bullet's solvers only turn points
/// with distance <= that threshold into constraints.
/// Sleeping, the Bullet way: a body that is not active is at rest with infinite mass for the step (no impulse,
/// no activate()); Bullet's island manager wakes it when its island has an active member.
/// Kinematic bodies are moving bodies of infinite mass: their velocity counts, the clamp never rewinds or drops
/// their pairs (time_of_impact_clamp.h). Compound children each get their own pose (motion_prediction.h).
///
/// Thread safety: one system per world; Bullet's narrowphase must be single threaded (btDiscreteDynamicsWorld,
/// not btDiscreteDynamicsWorldMt: the constructor refuses the Mt world and dispatcher). Models are shared read-only.
/// Inside the step the CCD of our pairs runs on our own pool (ContactSettings::threads), touching no Bullet
/// object; Bullet sees the results serially, in its pair order (bullet_ext/src/step/step_planner.cpp).
/// Use (the world is the program's; the contact system lives between the world's construction and destruction):
/// @code
///   btDiscreteDynamicsWorld world(&dispatcher, &broadphase, solver.get(), &configuration);
///   sdfccd::bullet::ContactSystem contacts(world);  // our algorithms for every pair of SdfccdShape, and the action
///   world.stepSimulation(dt, 0);
///   contacts.lastStepContacts();                     // what touched what in the last step
/// @endcode
#pragma once

#include <memory>
#include <vector>

#include "sdfccd/bullet/contact_settings.h"

class btCollisionDispatcher;
class btCollisionObject;
class btCollisionWorld;

namespace sdfccd::bullet {

namespace detail {
class ContactStep;
struct ContactSystemAccess;
}  // namespace detail

/// Ownership: the program owns the ContactSystem (Bullet's rule for what Bullet points at: the dispatcher's create
/// functions and the world's action are this object's). Construct it after the world and destroy it before; its
/// destructor removes the action, frees the algorithms of the world's current pairs that point at it (ours, and
/// compound children of ours) and points every dispatcher entry of our shape type at btEmptyAlgorithm (no
/// contact), so the world stays usable without it. A dispatcher takes one live ContactSystem at a time.
///
/// Threads: the narrowphase must run on one thread. A btDiscreteDynamicsWorldMt or a btCollisionDispatcherMt is
/// refused (sdfccd::Error); use btDiscreteDynamicsWorld with btCollisionDispatcher. In solver mode (the default)
/// build the world with the constraint solver of contact_solver.h (makeContactSolver, configureContactSolver):
/// Bullet's default sequential-impulse solver lets stacks and heavy-on-light pairs creep.
///
/// Which pairs: our algorithm for (ours, X) and (X, ours), contacts and closest points, for every X but compounds
/// (Bullet's compound algorithms stay, and dispatch each child pair back to ours) and btEmptyShape. A convex X takes
/// both roles like ours: its surface points (sampled once per size, convexPointSpacingCells) against our field, and
/// our shell against its exact field (BoxField, SphereField, CapsuleField; RevolvedConvexField for cylinders and
/// cones; the ConvexPolytopeField of its hull for any other convex shape). Triangle meshes and terrain: our shell
/// against the triangles near our body, their vertices against our field. Any other X is announced once
/// (setLogCallback) and counted in unsupportedPairs.
class ContactSystem {
 public:
  /// Installs the contact in `world`: registers our algorithms with its dispatcher (a btCollisionDispatcher) and,
  /// for a dynamics world, adds the response as an action and plans each step's pairs (ContactSettings::threads).
  /// Throws sdfccd::Error on a multi-threaded world or dispatcher, a dispatcher that has a live ContactSystem, and
  /// bad settings.
  explicit ContactSystem(btCollisionWorld& world, const ContactSettings& settings = {});
  /// Registers with `dispatcher` alone (collision queries without a world: no action, no planning). Throws as above.
  explicit ContactSystem(btCollisionDispatcher& dispatcher, const ContactSettings& settings = {});
  ~ContactSystem();
  ContactSystem(const ContactSystem&) = delete;
  ContactSystem& operator=(const ContactSystem&) = delete;

  const ContactSettings& settings() const;
  /// Takes effect at the next step. Throws sdfccd::Error on bad values.
  void setSettings(const ContactSettings& settings);

  /// Per-body penalty parameters (see BodyContact), taking effect at the next step. The body is a key only (not
  /// owned, never dereferenced): clear its entry when the body is destroyed, or a new body at its address inherits
  /// it. Throws sdfccd::Error on a null body or bad values.
  void setBodyContact(const btCollisionObject* body, const BodyContact& contact);
  void clearBodyContact(const btCollisionObject* body);
  /// The body's override, or null.
  const BodyContact* bodyContact(const btCollisionObject* body) const;

  /// The roles that had contact in the last completed step.
  const std::vector<PairContact>& lastStepContacts() const;
  /// Total contact points and largest penetration (cells) of the last completed step.
  int lastStepContactCount() const;
  double lastStepMaxPenetrationCells() const;
  int lastStepClamps() const;
  const ContactStatistics& statistics() const;
  /// Where the one-line announcements go (an unsupported pair of shape types, once per type pair and system);
  /// stderr by default; an empty callback silences them. The pairs are counted in
  /// ContactStatistics::unsupportedPairs either way.
  void setLogCallback(LogCallback callback);

 private:
  friend struct detail::ContactSystemAccess;  // the library's own parts and the benchmarks' hooks
  std::unique_ptr<detail::ContactStep> m_step;
  btCollisionWorld* m_world = nullptr;            // null when registered with a dispatcher alone
  btCollisionDispatcher* m_dispatcher = nullptr;  // whose entries point at m_step's create functions
  bool m_action = false;                          // m_step is the world's action
};

}  // namespace sdfccd::bullet
