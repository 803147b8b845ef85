/// @file
/// @brief BodySteps: each collision object's motion over the current step (motion_prediction.h), made once per step
/// at the object's first pair and kept for its other pairs and for the response after integrateTransforms.
#pragma once

#include <cstddef>
#include <unordered_map>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/response/penalty_model.h"

class btCollisionObject;
class btCollisionObjectWrapper;
class btRigidBody;

namespace sdfccd::bullet::detail {

class ContactLoads;

/// One body's frames as a penalty role's input takes them (penalty_role.h: fillPenaltyInput), for one pair of child
/// frames (the keys: the frames' addresses, which stay put through the step).
struct RoleFrames {
  bool set = false;
  const Rigid* key0 = nullptr;  // the shell's child frame, or the field's child frame
  const Rigid* key1 = nullptr;  // the field's frame in its child (null for the shell)
  Rigid worldFromStart = Rigid::Identity();
  Rigid worldFromEnd = Rigid::Identity();
  Vec3 centerOfMass = Vec3::Zero();
};

/// The motion of one collision object over the current step (motion_prediction.h).
struct BodyStep {
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
  RoleFrames shellFrames;
  RoleFrames fieldFrames;

  bool finiteState = true;  // finite(), taken once when the step is made (the poses and velocities do not change)

  /// The poses' and velocities' entries all finite (Eigen's allFinite(), the same answer, was out of line and ran
  /// for both bodies of every pair).
  bool finite() const {
    return finiteValues(worldFromBodyStart.data(), 16) && finiteValues(worldFromBodyEnd.data(), 16) &&
           finiteValues(velocity.linearStart.data(), 3) && finiteValues(velocity.linearEnd.data(), 3) &&
           finiteValues(velocity.angularStart.data(), 3) && finiteValues(velocity.angularEnd.data(), 3);
  }
};

/// The step's bodies, each once, in the order their first pair met them.
class BodySteps {
 public:
  /// The index of the wrapper's object's step, made at its first call of the step. `massScaling`: the loads whose
  /// contact mass a dynamic body takes (ContactLoads::applyContactMass; it changes velocities), or null.
  std::size_t indexOf(const btCollisionObjectWrapper* wrap, double timeStep, const ContactLoads* massScaling,
                      const StabilityCapSettings& caps);
  /// A pair's bodies (the first stage of a pair): their indices, false when a body's state is not finite (set by the
  /// user; Bullet integrates whatever it is given): such a pair takes no contact, so its impulses never carry a NaN
  /// into the other body.
  bool pairOf(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1, double timeStep,
              const ContactLoads* massScaling, const StabilityCapSettings& caps, std::size_t& index0,
              std::size_t& index1);

  BodyStep& operator[](std::size_t i) { return m_bodies[i]; }
  const BodyStep& operator[](std::size_t i) const { return m_bodies[i]; }
  std::vector<BodyStep>& all() { return m_bodies; }
  std::size_t size() const { return m_bodies.size(); }
  /// Room for `more` bodies: planned roles point into the steps, which must not move while the pool reads them.
  void reserveMore(std::size_t more) { m_bodies.reserve(m_bodies.size() + more); }
  /// Forgets the step's bodies (after the response).
  void clear();

  /// A closest-point query's own bodies for its lifetime (poses now, nothing moves); the step's come back after.
  class FreshScope {
   public:
    explicit FreshScope(BodySteps& steps);
    ~FreshScope();
    FreshScope(const FreshScope&) = delete;
    FreshScope& operator=(const FreshScope&) = delete;

   private:
    BodySteps& m_steps;
    std::vector<BodyStep> m_savedBodies;
    std::unordered_map<const btCollisionObject*, std::size_t> m_savedIndex;
  };

 private:
  std::vector<BodyStep> m_bodies;
  std::unordered_map<const btCollisionObject*, std::size_t> m_index;
  // A guess per world array index (btCollisionObject::getWorldArrayIndex) of the object's place in m_bodies, tried
  // before the map (indexOf): right when that place holds the object, never reset.
  std::vector<std::size_t> m_guess;
};

}  // namespace sdfccd::bullet::detail
