/// @file
/// @brief The procedural alpha puzzle piece (paper Section 5, Fig. 1 and "Haptic Rendering": the alpha puzzle,
/// two identical alpha-shaped tubes that interlock, a 25,000-point shell against a 512^3 field).
///
/// @details The paper's meshes are not available; this piece is a stand-in of the same kind: a tube of circular
/// cross-section along an "alpha" curve, the nodal cubic y^2 = x^2 (x + 1) lifted out of its plane,
///   c(t) = (t^2 - 1,  loopWidth * t (t^2 - 1),  crossingGap * t),    t in [-tailParameter, tailParameter].
/// For |t| < 1 the curve runs round a loop (x in [-1, 0]); at t = -1 and t = +1 it passes the origin's
/// (x, y) twice, at z = -crossingGap and z = +crossingGap, so the loop crosses near itself without touching;
/// the two tails (|t| > 1) leave towards +x. With the defaults the tube's surfaces at the crossing are
/// 2 (crossingGap - radius) = 0.3 apart, the curve's smallest radius of curvature is 0.248 (radius 0.15), the
/// length is 8.65 and the box is about [-1.15, 1.25] x [-2.45, 2.45] x [-0.59, 0.59] (tests check these).
///
/// Two pieces interlock like chain links: the second piece is the first mapped by
/// alphaPuzzleInterlockedPose() (x -> -x, then the loop turned into the xz plane, shifted along -x), so that each
/// loop threads the other's tube (the pieces start about 0.09 apart with the defaults).
#pragma once

#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd {

/// Shape of the alpha piece (model units).
struct AlphaPuzzlePieceSettings {
  double loopWidth = 1.5;       ///< scale of the curve's y (the loop's width)
  double crossingGap = 0.3;     ///< half the z separation of the curve where the loop crosses itself
  double tailParameter = 1.45;  ///< the curve parameter's end (> 1: the tails' length)
  double radius = 0.15;         ///< tube radius
  int samples = 320;            ///< rings along the curve (equally spaced by length)
  int segments = 24;            ///< vertices per ring
};

/// The alpha curve, `settings.samples` points equally spaced by length. Throws sdfccd::Error on absurd
/// settings (non-positive or non-finite sizes, tailParameter <= 1, samples < 2).
std::vector<Vec3> alphaPuzzleCurve(const AlphaPuzzlePieceSettings& settings = {});

/// The closed, outward tube mesh of one piece, in the curve's frame (see @details). Throws sdfccd::Error on
/// absurd settings.
TriangleMesh makeAlphaPuzzlePiece(const AlphaPuzzlePieceSettings& settings = {});

/// Where the second piece sits, interlocked with the first, in the curve's frame (the mesh of the second
/// piece is alphaPuzzleInterlockedPose() * first piece's mesh). Depends only on the curve's size: the loop
/// spans x in [-1, 0], so the second piece is shifted by -1.5 along x.
Rigid alphaPuzzleInterlockedPose();

}  // namespace sdfccd
