/// @file
/// @brief makeSweptTube: a closed triangle mesh of a tube of circular cross-section swept along a space curve
/// (the alpha puzzle pieces of paper Section 5, "Haptic Rendering").
///
/// @details The curve is an open polyline of samples. Each sample gets a ring of `segments` vertices on the
/// circle of `radius` in the plane normal to the curve's tangent (central differences inside, one-sided at
/// the ends). The rings' reference directions follow the curve by parallel transport (each frame is the
/// previous one turned by the smallest rotation that maps the previous tangent onto the next, Eigen's
/// Quaternion::FromTwoVectors), so the tube does not twist. Consecutive rings are joined by quads split into
/// two triangles, and each end is closed by a flat cap fan around the end sample. The mesh is closed
/// (watertight, manifold) and oriented outward (positive signed volume).
///
/// Valid tube (no self-intersection) needs radius below the curve's smallest radius of curvature and
/// non-neighbouring parts of the curve more than 2 radius apart; that is the caller's geometry, not checked
/// here. The enclosed volume then tends to pi radius^2 * length (Pappus) as the samples and segments grow;
/// the polygonal cross-section holds sin(2 pi / segments) / (2 pi / segments) of the disc's area.
#pragma once

#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd {

/// The length of a polyline (model units).
double polylineLength(const std::vector<Vec3>& curve);

/// Resamples a polyline at `samples` points equally spaced along its length (first and last points kept).
/// Throws sdfccd::Error on fewer than 2 input points, a zero length, non-finite points or samples < 2.
std::vector<Vec3> resamplePolylineByLength(const std::vector<Vec3>& curve, int samples);

/// The tube of `radius` around the polyline `curve` (at least 2 samples, consecutive samples distinct),
/// `segments` (>= 3) vertices per ring, flat end caps. Throws sdfccd::Error on bad input (too few samples,
/// repeated consecutive samples, non-finite values, radius <= 0, segments < 3).
TriangleMesh makeSweptTube(const std::vector<Vec3>& curve, double radius, int segments = 24);

}  // namespace sdfccd
