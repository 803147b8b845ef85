/// @file
/// @brief makeSweptTube and the alpha puzzle piece: closed, outward, the analytic tube volume (Pappus), and
/// the piece's geometry (no self-intersection, the interlocked pair apart but close).
#include "sdfccd/model/swept_tube.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/shell_test_util.h"
#include "sdfccd/error.h"
#include "sdfccd/model/alpha_puzzle_piece.h"

namespace sdfccd {
namespace {

// Area of the regular polygon of `segments` sides inscribed in the circle of radius r.
double polygonArea(double r, int segments) {
  return 0.5 * segments * r * r * std::sin(2.0 * kPi / segments);
}

// Circumradius of three consecutive samples (the discrete radius of curvature; infinite when collinear).
double circumradius(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double cross = (b - a).cross(c - a).norm();
  if (cross == 0.0) return std::numeric_limits<double>::infinity();
  return (b - a).norm() * (c - b).norm() * (a - c).norm() / (2.0 * cross);
}

TEST(SweptTube, StraightTubeIsThePrismOfTheRing) {
  std::vector<Vec3> line;
  for (int i = 0; i <= 10; ++i) line.emplace_back(0.1 * i, 0.2 * i, -0.05 * i);
  const double length = polylineLength(line);
  const TriangleMesh tube = makeSweptTube(line, 0.3, 16);
  EXPECT_TRUE(test::closedAndOriented(tube));
  EXPECT_EQ(tube.triangles.size(), 10u * 16u * 2u + 2u * 16u);
  EXPECT_NEAR(test::volume(tube), polygonArea(0.3, 16) * length, 1e-12);
  // Every ring vertex is at the radius from the axis.
  for (std::size_t v = 0; v + 2 < tube.vertices.size(); ++v)
    EXPECT_NEAR(test::segmentDistance(tube.vertices[v], line.front(), line.back()), 0.3, 1e-12);
}

TEST(SweptTube, HalfTorusHasThePappusVolume) {
  // A half circle of radius 2 (in the xz plane), tube radius 0.4: volume = pi r^2 * (pi R).
  std::vector<Vec3> arc;
  for (int i = 0; i <= 400; ++i) {
    const double a = kPi * i / 400;
    arc.emplace_back(2.0 * std::cos(a), 0.0, 2.0 * std::sin(a));
  }
  const TriangleMesh tube = makeSweptTube(arc, 0.4, 48);
  EXPECT_TRUE(test::closedAndOriented(tube));
  const double exact = kPi * 0.16 * kPi * 2.0;
  EXPECT_NEAR(test::volume(tube), exact, 0.01 * exact);
  EXPECT_LT(test::volume(tube), exact);  // inscribed polygons
}

TEST(SweptTube, RejectsBadInput) {
  const std::vector<Vec3> line{Vec3(0, 0, 0), Vec3(1, 0, 0)};
  EXPECT_THROW(makeSweptTube({Vec3::Zero()}, 0.1), Error);
  EXPECT_THROW(makeSweptTube(line, 0.0), Error);
  EXPECT_THROW(makeSweptTube(line, std::nan(""), 8), Error);
  EXPECT_THROW(makeSweptTube(line, 0.1, 2), Error);
  EXPECT_THROW(makeSweptTube({Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)}, 0.1), Error);
  EXPECT_THROW(makeSweptTube({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 0)}, 0.1), Error);  // folds back
  EXPECT_THROW(makeSweptTube({Vec3(0, 0, 0), Vec3(1, std::nan(""), 0)}, 0.1), Error);
  EXPECT_THROW(resamplePolylineByLength({Vec3::Zero(), Vec3::Zero()}, 5), Error);
}

TEST(SweptTube, ResamplingIsEquallySpacedAndKeepsTheEnds) {
  const std::vector<Vec3> bent{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 3, 0)};
  const std::vector<Vec3> even = resamplePolylineByLength(bent, 9);
  ASSERT_EQ(even.size(), 9u);
  EXPECT_EQ(even.front(), bent.front());
  EXPECT_EQ(even.back(), bent.back());
  EXPECT_NEAR((even[2] - Vec3(1, 0, 0)).norm(), 0.0, 1e-12);  // 4 / 8 * 2 = 1: the corner
  for (std::size_t i = 1; i < even.size(); ++i) EXPECT_NEAR((even[i] - even[i - 1]).norm(), 0.5, 1e-12);
}

TEST(AlphaPuzzlePiece, ClosedOutwardWithTheTubeVolume) {
  const AlphaPuzzlePieceSettings settings;
  const TriangleMesh piece = makeAlphaPuzzlePiece(settings);
  EXPECT_TRUE(test::closedAndOriented(piece));
  const double length = polylineLength(alphaPuzzleCurve(settings));
  EXPECT_NEAR(length, 8.65, 0.01);
  const double exact = kPi * settings.radius * settings.radius * length;
  const double v = test::volume(piece);
  EXPECT_GT(v, 0.97 * exact);
  EXPECT_LT(v, 1.01 * exact);
  const Box3 box = piece.bounds();
  EXPECT_NEAR(box.min().x(), -1.15, 0.01);
  EXPECT_NEAR(box.max().x(), 1.25, 0.02);
  EXPECT_NEAR(box.sizes().y(), 4.9, 0.01);  // the end caps face almost along y
  EXPECT_NEAR(box.sizes().z(), 1.18, 0.02);
  EXPECT_THROW(makeAlphaPuzzlePiece({1.5, 0.3, 1.0}), Error);  // no tails
  AlphaPuzzlePieceSettings bad;
  bad.radius = -1.0;
  EXPECT_THROW(makeAlphaPuzzlePiece(bad), Error);
}

TEST(AlphaPuzzlePiece, TubeDoesNotIntersectItself) {
  AlphaPuzzlePieceSettings settings;
  const std::vector<Vec3> curve = alphaPuzzleCurve(settings);
  const double spacing = polylineLength(curve) / static_cast<double>(curve.size() - 1);
  // Locally: the radius of curvature stays above the tube radius (0.248 analytically).
  double smallest = 1e300;
  for (std::size_t i = 1; i + 1 < curve.size(); ++i)
    smallest = std::min(smallest, circumradius(curve[i - 1], curve[i], curve[i + 1]));
  EXPECT_NEAR(smallest, 0.248, 0.01);
  EXPECT_GT(smallest, 1.5 * settings.radius);
  // Globally: parts of the curve more than 1.2 apart along it stay more than a tube diameter apart (the
  // nearest pass is the crossing: 2 crossingGap).
  double nearest = 1e300;
  for (std::size_t i = 0; i < curve.size(); ++i)
    for (std::size_t j = i + 1; j < curve.size(); ++j)
      if (static_cast<double>(j - i) * spacing > 1.2) nearest = std::min(nearest, (curve[i] - curve[j]).norm());
  EXPECT_GT(nearest, 2.0 * settings.radius + 0.28);
  EXPECT_LT(nearest, 2.0 * settings.crossingGap + 1e-9);
}

TEST(AlphaPuzzlePiece, InterlockedPairIsCloseButApart) {
  const AlphaPuzzlePieceSettings settings;
  const std::vector<Vec3> curve = alphaPuzzleCurve(settings);
  const Rigid second = alphaPuzzleInterlockedPose();
  EXPECT_NEAR(second.linear().determinant(), 1.0, 1e-15);
  double nearest = 1e300;
  for (const Vec3& a : curve)
    for (const Vec3& b : curve) nearest = std::min(nearest, (a - second * b).norm());
  EXPECT_GT(nearest, 2.0 * settings.radius + 0.05);
  EXPECT_LT(nearest, 2.0 * settings.radius + 0.15);
  // Each loop threads the other: the second piece's loop tip (the curve at t = 0, (-1, 0, 0) mapped) lies
  // inside the first loop's hole (x in (-1, 0) on the axis), and vice versa.
  const Vec3 secondTip = second * Vec3(-1.0, 0.0, 0.0);
  EXPECT_NEAR(secondTip.x(), -0.5, 1e-12);
  const Vec3 firstTipInSecond = second.inverse() * Vec3(-1.0, 0.0, 0.0);
  EXPECT_NEAR(firstTipInSecond.x(), -0.5, 1e-12);
}

}  // namespace
}  // namespace sdfccd
