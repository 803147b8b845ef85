/// @file
/// @brief ContactRecord: one role of one pair over the current step, as the narrowphase leaves it for the response
/// after integrateTransforms (step_response.cpp): its penalty result, its clamp and the points the clamp stops.
#pragma once

#include <cstddef>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/response/penalty_model.h"
#include "sdfccd/response/time_of_impact_clamp.h"

namespace sdfccd::bullet::detail {

struct ContactRecord {
  std::size_t shell = 0;  // indices into the step's bodies (BodySteps)
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

constexpr std::size_t kMaxClampPoints = 32;   // impact points per record
constexpr int kImpactIterations = 8;          // sequential-impulse sweeps over them
constexpr double kConvexPointsAcross = 16.0;  // convex shapes: at least this many points across their thinnest size

}  // namespace sdfccd::bullet::detail
