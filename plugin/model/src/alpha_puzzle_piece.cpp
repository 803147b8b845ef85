/// @file
/// @brief The alpha puzzle piece (see alpha_puzzle_piece.h).
#include "sdfccd/model/alpha_puzzle_piece.h"

#include <cmath>

#include "sdfccd/error.h"
#include "sdfccd/model/swept_tube.h"

namespace sdfccd {

std::vector<Vec3> alphaPuzzleCurve(const AlphaPuzzlePieceSettings& s) {
  const auto finitePositive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!finitePositive(s.loopWidth) || !finitePositive(s.crossingGap) || !finitePositive(s.radius))
    throw Error("alpha puzzle piece: loopWidth, crossingGap and radius must be positive and finite");
  if (!(s.tailParameter > 1.0) || !std::isfinite(s.tailParameter) || s.tailParameter > 10.0)
    throw Error("alpha puzzle piece: tailParameter must be in (1, 10]");
  if (s.samples < 2 || s.samples > 100000) throw Error("alpha puzzle piece: samples must be in [2, 100000]");
  // Dense in the parameter first, then equally spaced by length (the speed varies about 6x along the curve).
  const int dense = 16 * s.samples;
  std::vector<Vec3> curve;
  curve.reserve(static_cast<std::size_t>(dense + 1));
  for (int i = 0; i <= dense; ++i) {
    const double t = -s.tailParameter + 2.0 * s.tailParameter * i / dense;
    curve.emplace_back(t * t - 1.0, s.loopWidth * t * (t * t - 1.0), s.crossingGap * t);
  }
  return resamplePolylineByLength(curve, s.samples);
}

TriangleMesh makeAlphaPuzzlePiece(const AlphaPuzzlePieceSettings& settings) {
  if (settings.segments < 3 || settings.segments > 4096)
    throw Error("alpha puzzle piece: segments must be in [3, 4096]");
  return makeSweptTube(alphaPuzzleCurve(settings), settings.radius, settings.segments);
}

Rigid alphaPuzzleInterlockedPose() {
  // (x, y, z) -> (-x - 1.5, -z, -y): a rotation (determinant +1), so the mesh stays outward.
  Rigid pose = Rigid::Identity();
  pose.linear() << -1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, -1.0, 0.0;
  pose.translation() = Vec3(-1.5, 0.0, 0.0);
  return pose;
}

}  // namespace sdfccd
