/// @file
/// @brief What SdfccdContactSystem records during one step (Section 4.1 and 5): each body's motion, each
/// role's penalty result and clamping, and who is shell and who field in a role. Private to sdfccd::bullet:
/// shared by the narrowphase (sdfccd_contact_system.cpp) and the response (sdfccd_contact_response.cpp).
#pragma once

#include <cstddef>
#include <vector>

#include "sdfccd/bullet/sdfccd_contact_system.h"

class btRigidBody;

namespace sdfccd {

/// The motion of one collision object over the current step.
struct SdfccdContactSystem::BodyStep {
  const btCollisionObject* object = nullptr;
  btRigidBody* body = nullptr;  // null unless a dynamic rigid body
  Rigid worldFromBodyStart = Rigid::Identity();
  Rigid worldFromBodyEnd = Rigid::Identity();
  BodyVelocities velocity;  // of the centre of mass, which is the body origin
  double clampFraction = 1.0;
  bool clamped = false;

  bool finite() const {
    return worldFromBodyStart.matrix().allFinite() && worldFromBodyEnd.matrix().allFinite() && velocity.allFinite();
  }
};

/// One role of one pair over the current step.
struct SdfccdContactSystem::Record {
  std::size_t shell = 0;  // indices into m_bodies
  std::size_t field = 0;
  PenaltyResult penalty;
  double maxPenetrationCells = 0.0;
  double firstFraction = 1.0;
  bool clamp = false;
  bool applied = false;  // SameStep: the penalty impulses are already in the velocities
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
  bool shellIsBody0 = true;
};

}  // namespace sdfccd
