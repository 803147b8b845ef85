/// @file
/// @brief The numerical tolerances of sdfccd, in one place: each with its unit and the reason it exists
/// (FCL and Jolt's PhysicsSettings.h are the examples).
///
/// @details Most are margins against rounding that keep a conservative test conservative: a bound computed
/// with one rounding must still hold for a value computed with another (a node centre's segment against the
/// points' own segments, a whole-grid pass against the segment query's own interpolation). They are small
/// enough never to matter for a contact, and changing one changes results bit for bit: the golden hash
/// (tests/bullet/golden_hash_test.cpp) guards them.
#pragma once

namespace sdfccd::tolerance {

/// Relative slack (dimensionless) of a bound computed in floating point: a Lipschitz bound, a reach, an
/// accumulated travel or a clearance is grown (or shrunk) by this fraction of itself so that the rounding of
/// the quantities it bounds stays on the safe side.
constexpr double kRelativeSlack = 1e-9;

/// `bound * kBoundGrowth`: a bound grown by kRelativeSlack (dimensionless factor 1 + 1e-9). Used for the
/// culling radius of a tree node, the Lipschitz early-out, the grid's gradient bounds (whole grid and per
/// block) and the god-object's clearance cache.
constexpr double kBoundGrowth = 1.0 + kRelativeSlack;

/// Margin on fractions of the step (fraction of the step, dimensionless) where a search is cut short or a
/// lower bound of a first contact is taken: a shorter walk rounds differently from the whole one, and a node
/// centre's first hit differs by rounding from its points'. Moves a cut later, or a lower bound earlier.
constexpr double kFractionSlack = 1e-9;

/// Sub-intervals of a segment query closer than this (fraction of the step) are merged: across a cell face
/// the two cells' cubics agree only to rounding, which can open a gap of a few ulps where the true field
/// stays in contact.
constexpr double kIntervalMergeGap = 1e-12;

/// Regula falsi (the bisection method, eq. 2) stops when |g| <= kRegulaFalsiResidual * (|g_in| + |g_out|)
/// (relative to the values at the cell's entry and exit, dimensionless): the root is then as good as the
/// cubic's own rounding.
constexpr double kRegulaFalsiResidual = 1e-12;

/// Safeguarded Newton on a cell's cubic stops when a step is at most this long (fraction of the cell's part of
/// the segment): below the resolution of doubles near 1.
constexpr double kNewtonMinStep = 1e-17;
/// After Newton, the root is nudged towards the contact side by growing amounts (times 4 from
/// kRootNudgeFirst while below kRootNudgeLast, fractions of the cell's part of the segment) until the cubic is
/// <= 0 there, so the reported fraction is in contact: a few ulps first, never more than ~1e-9.
constexpr double kRootNudgeFirst = 2.5e-16;
constexpr double kRootNudgeLast = 1e-9;  ///< see kRootNudgeFirst

/// A direction (a field gradient, a point normal, a quaternion) shorter than this is no direction (units of
/// the vector: a gradient in model units per model unit, a normal or quaternion dimensionless). Such a point
/// gives no constraint or stiffness; a file with such a normal is rejected.
constexpr double kMinDirectionLength = 1e-12;

/// A point normal read from a file must have unit length within this (dimensionless).
constexpr double kUnitNormalTolerance = 1e-6;

/// Counting cells or samples along a length: ceil(length / size - kCountRounding), so a ratio that exceeds an
/// integer only by rounding (dimensionless) does not add one more.
constexpr double kCountRounding = 1e-9;

/// A triangle is degenerate when |(b - a) x (c - a)| <= kCollinearity * (longest edge)^2 (dimensionless: its
/// largest angle is below ~1e-12, collinear to double rounding).
constexpr double kCollinearity = 1e-12;

/// Inertia with off-diagonal terms under kPrincipalAxesTolerance * trace (dimensionless) is taken as already
/// principal: symmetric shapes have ill-defined principal axes, and rotating them would only add rounding.
constexpr double kPrincipalAxesTolerance = 1e-9;

/// The SDF builder's BVH search radius, |centre - closest| + block radius, is grown by this factor
/// (dimensionless) so that a triangle at exactly that distance is not lost to rounding.
constexpr double kSearchRadiusGrowth = 1.0 + 1e-12;

/// LocalLipschitzBounds' reach is a block size shrunk by this fraction (dimensionless), for the rounding of
/// the block lookup.
constexpr double kBlockReachShrink = 1e-6;

}  // namespace sdfccd::tolerance
