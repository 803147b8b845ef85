/// @file
/// @brief PlaneField and SphereField: closed-form segment queries against hand-computed answers and dense
/// sampling; the edge-case policy of segment_ccd.h (touching, starting inside, zero length, FirstHit, NaN).
#include "sdfccd/analytic_fields.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

SegmentCcdSettings allIntervals(double sigma = 0.0) {
  SegmentCcdSettings s;
  s.sigma = sigma;
  s.mode = CcdMode::AllIntervals;
  return s;
}

TEST(PlaneField, DistanceGradientAndNormalization) {
  const PlaneField plane(Vec3(0.0, 2.0, 0.0), 1.5);
  EXPECT_DOUBLE_EQ(plane.normal().norm(), 1.0);
  EXPECT_DOUBLE_EQ(plane.distance(Vec3(4.0, 3.0, -2.0)), 1.5);
  EXPECT_DOUBLE_EQ(plane.distance(Vec3(0.0, 0.0, 0.0)), -1.5);
  EXPECT_TRUE(plane.gradient(Vec3(9.0, 9.0, 9.0)).isApprox(Vec3::UnitY()));
  EXPECT_TRUE(plane.contains(Vec3(1e9, -1e9, 0.0)));
  EXPECT_DOUBLE_EQ(PlaneField::ground().distance(Vec3(1.0, 0.25, 3.0)), 0.25);
  EXPECT_THROW(PlaneField(Vec3::Zero(), 0.0), Error);
  EXPECT_THROW(PlaneField(Vec3(std::nan(""), 0.0, 1.0), 0.0), Error);
  EXPECT_THROW(PlaneField(Vec3::UnitZ(), std::numeric_limits<double>::infinity()), Error);
}

TEST(PlaneField, CrossingTimeIsLinearInterpolation) {
  const PlaneField ground = PlaneField::ground();
  // From y = 3 to y = -1: crosses y = 0 at t = 3/4, in contact on [3/4, 1].
  const auto r = ground.intersectSegment(Vec3(0.2, 3.0, 0.0), Vec3(1.0, -1.0, 0.5), allIntervals());
  EXPECT_EQ(r.state, SegmentState::Hit);
  EXPECT_DOUBLE_EQ(r.fraction, 0.75);
  ASSERT_EQ(r.intervals.size(), 1u);
  EXPECT_DOUBLE_EQ(r.intervals[0].begin, 0.75);
  EXPECT_DOUBLE_EQ(r.intervals[0].end, 1.0);
  EXPECT_TRUE(r.normal.isApprox(Vec3::UnitY()));
  EXPECT_DOUBLE_EQ(r.depth, 0.0);
  // With sigma = 1 the level set y = 1 is reached at t = 1/2.
  const auto s = ground.intersectSegment(Vec3(0.0, 3.0, 0.0), Vec3(0.0, -1.0, 0.0), allIntervals(1.0));
  EXPECT_DOUBLE_EQ(s.fraction, 0.5);
  // Moving up out of the ground: starts inside, leaves at t = 1/4.
  const auto u = ground.intersectSegment(Vec3(0.0, -1.0, 0.0), Vec3(0.0, 3.0, 0.0), allIntervals());
  EXPECT_EQ(u.state, SegmentState::StartsInside);
  EXPECT_DOUBLE_EQ(u.fraction, 0.0);
  EXPECT_DOUBLE_EQ(u.depth, -1.0);
  ASSERT_EQ(u.intervals.size(), 1u);
  EXPECT_DOUBLE_EQ(u.intervals[0].begin, 0.0);
  EXPECT_DOUBLE_EQ(u.intervals[0].end, 0.25);
  // Separated: both ends above.
  const auto v = ground.intersectSegment(Vec3(0.0, 1.0, 0.0), Vec3(5.0, 0.1, 0.0), allIntervals());
  EXPECT_EQ(v.state, SegmentState::Separated);
  EXPECT_DOUBLE_EQ(v.fraction, 1.0);
  EXPECT_TRUE(v.intervals.empty());
}

TEST(PlaneField, TouchingCountsZeroLengthIsAPointQueryFirstHitHasNoIntervals) {
  const PlaneField ground = PlaneField::ground();
  // Ends exactly on the plane: a hit at t = 1 with a degenerate interval.
  const auto touch = ground.intersectSegment(Vec3(0.0, 2.0, 0.0), Vec3(0.0, 0.0, 0.0), allIntervals());
  EXPECT_EQ(touch.state, SegmentState::Hit);
  EXPECT_DOUBLE_EQ(touch.fraction, 1.0);
  ASSERT_EQ(touch.intervals.size(), 1u);
  EXPECT_DOUBLE_EQ(touch.intervals[0].begin, 1.0);
  // Sliding along the plane: starts inside (touching), in contact all step.
  const auto slide = ground.intersectSegment(Vec3(0.0, 0.0, 0.0), Vec3(3.0, 0.0, 0.0), allIntervals());
  EXPECT_EQ(slide.state, SegmentState::StartsInside);
  EXPECT_DOUBLE_EQ(slide.intervals[0].end, 1.0);
  // Zero length.
  EXPECT_EQ(ground.intersectSegment(Vec3(1, 2, 3), Vec3(1, 2, 3), allIntervals()).state, SegmentState::Separated);
  const auto inside = ground.intersectSegment(Vec3(1, -2, 3), Vec3(1, -2, 3), allIntervals());
  EXPECT_EQ(inside.state, SegmentState::StartsInside);
  EXPECT_DOUBLE_EQ(inside.depth, -2.0);
  // FirstHit: no intervals.
  SegmentCcdSettings first;
  const auto f = ground.intersectSegment(Vec3(0.0, 1.0, 0.0), Vec3(0.0, -1.0, 0.0), first);
  EXPECT_EQ(f.state, SegmentState::Hit);
  EXPECT_DOUBLE_EQ(f.fraction, 0.5);
  EXPECT_TRUE(f.intervals.empty());
  // Non-finite input fails.
  EXPECT_EQ(ground.intersectSegment(Vec3(std::nan(""), 0, 0), Vec3::Zero(), first).state, SegmentState::Failed);
  SegmentCcdSettings nanSigma;
  nanSigma.sigma = std::nan("");
  EXPECT_EQ(ground.intersectSegment(Vec3::Zero(), Vec3::Ones(), nanSigma).state, SegmentState::Failed);
}

TEST(SphereField, DistanceAndGradient) {
  const SphereField sphere(Vec3(1.0, 2.0, 3.0), 0.5);
  EXPECT_DOUBLE_EQ(sphere.distance(Vec3(1.0, 2.0, 5.0)), 1.5);
  EXPECT_DOUBLE_EQ(sphere.distance(Vec3(1.0, 2.0, 3.0)), -0.5);
  EXPECT_TRUE(sphere.gradient(Vec3(4.0, 2.0, 3.0)).isApprox(Vec3::UnitX()));
  EXPECT_TRUE(sphere.gradient(Vec3(1.0, 2.0, 3.0)).isZero());
  EXPECT_THROW(SphereField(Vec3::Zero(), 0.0), Error);
  EXPECT_THROW(SphereField(Vec3::Zero(), -1.0), Error);
  EXPECT_THROW(SphereField(Vec3(0, std::nan(""), 0), 1.0), Error);
}

TEST(SphereField, ThroughTheCentreEntersAndLeavesAtClosedFormTimes) {
  const SphereField sphere(Vec3::Zero(), 1.0);
  // x from -3 to 3: inside on |x| <= 1, i.e. t in [1/3, 2/3].
  const auto r = sphere.intersectSegment(Vec3(-3.0, 0.0, 0.0), Vec3(3.0, 0.0, 0.0), allIntervals());
  EXPECT_EQ(r.state, SegmentState::Hit);
  EXPECT_NEAR(r.fraction, 1.0 / 3.0, 1e-15);
  ASSERT_EQ(r.intervals.size(), 1u);
  EXPECT_NEAR(r.intervals[0].begin, 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(r.intervals[0].end, 2.0 / 3.0, 1e-15);
  EXPECT_TRUE(r.normal.isApprox(-Vec3::UnitX(), 1e-12));
  // sigma = 0.5: the level set is the sphere of radius 1.5; x in [-1.5, 1.5] is t in [1/4, 3/4].
  const auto s = sphere.intersectSegment(Vec3(-3.0, 0.0, 0.0), Vec3(3.0, 0.0, 0.0), allIntervals(0.5));
  EXPECT_NEAR(s.intervals[0].begin, 0.25, 1e-15);
  EXPECT_NEAR(s.intervals[0].end, 0.75, 1e-15);
  // Offset chord at height h = 0.6: half chord sqrt(1 - 0.36) = 0.8, so x in [-0.8, 0.8].
  const auto c = sphere.intersectSegment(Vec3(-2.0, 0.6, 0.0), Vec3(2.0, 0.6, 0.0), allIntervals());
  EXPECT_NEAR(c.intervals[0].begin, (2.0 - 0.8) / 4.0, 1e-15);
  EXPECT_NEAR(c.intervals[0].end, (2.0 + 0.8) / 4.0, 1e-15);
  // A miss.
  EXPECT_EQ(sphere.intersectSegment(Vec3(-2.0, 1.2, 0.0), Vec3(2.0, 1.2, 0.0), allIntervals()).state,
            SegmentState::Separated);
  // A segment that stops before reaching the sphere.
  EXPECT_EQ(sphere.intersectSegment(Vec3(-3.0, 0.0, 0.0), Vec3(-1.5, 0.0, 0.0), allIntervals()).state,
            SegmentState::Separated);
  // A level set below -r is empty.
  EXPECT_EQ(sphere.intersectSegment(Vec3(-3.0, 0.0, 0.0), Vec3(3.0, 0.0, 0.0), allIntervals(-1.5)).state,
            SegmentState::Separated);
}

TEST(SphereField, GrazingStartingInsideAndZeroLength) {
  const SphereField sphere(Vec3::Zero(), 1.0);
  // Tangent line y = 1: touches at x = 0 (t = 1/2); touching counts.
  const auto g = sphere.intersectSegment(Vec3(-1.0, 1.0, 0.0), Vec3(1.0, 1.0, 0.0), allIntervals());
  EXPECT_EQ(g.state, SegmentState::Hit);
  EXPECT_NEAR(g.fraction, 0.5, 1e-15);
  ASSERT_EQ(g.intervals.size(), 1u);
  EXPECT_NEAR(g.intervals[0].end - g.intervals[0].begin, 0.0, 1e-15);
  // Starting inside at the centre, leaving at x = 1 (t = 1/4).
  const auto in = sphere.intersectSegment(Vec3::Zero(), Vec3(4.0, 0.0, 0.0), allIntervals());
  EXPECT_EQ(in.state, SegmentState::StartsInside);
  EXPECT_DOUBLE_EQ(in.fraction, 0.0);
  EXPECT_DOUBLE_EQ(in.depth, -1.0);
  EXPECT_NEAR(in.intervals[0].end, 0.25, 1e-15);
  // Entirely inside.
  const auto all = sphere.intersectSegment(Vec3(-0.5, 0, 0), Vec3(0.5, 0, 0), allIntervals());
  EXPECT_EQ(all.state, SegmentState::StartsInside);
  EXPECT_DOUBLE_EQ(all.intervals[0].end, 1.0);
  // Zero length outside and inside.
  EXPECT_EQ(sphere.intersectSegment(Vec3(2, 0, 0), Vec3(2, 0, 0), allIntervals()).state, SegmentState::Separated);
  EXPECT_EQ(sphere.intersectSegment(Vec3(0.5, 0, 0), Vec3(0.5, 0, 0), allIntervals()).state,
            SegmentState::StartsInside);
  // Ending exactly on the sphere.
  const auto end = sphere.intersectSegment(Vec3(3, 0, 0), Vec3(1, 0, 0), allIntervals());
  EXPECT_EQ(end.state, SegmentState::Hit);
  EXPECT_DOUBLE_EQ(end.fraction, 1.0);
  EXPECT_EQ(sphere.intersectSegment(Vec3(std::nan(""), 0, 0), Vec3(1, 0, 0), allIntervals()).state,
            SegmentState::Failed);
}

TEST(SphereField, RandomSegmentsMatchDenseSampling) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const SphereField sphere(Vec3(0.1, -0.2, 0.3), 1.2);
  int hits = 0;
  for (int n = 0; n < 2000; ++n) {
    const Vec3 p0(u(rng), u(rng), u(rng));
    const Vec3 p1(u(rng), u(rng), u(rng));
    const double sigma = 0.25 * u(rng) / 3.0;
    const auto r = sphere.intersectSegment(p0, p1, allIntervals(sigma));
    // Dense sampling: every sample inside the level set lies in a reported interval (to the sampling step),
    // and the first inside sample is at the reported first hit.
    const int samples = 4000;
    double firstInside = -1.0;
    for (int k = 0; k <= samples; ++k) {
      const double t = static_cast<double>(k) / samples;
      const bool inside = sphere.distance(p0 + t * (p1 - p0)) <= sigma;
      if (inside && firstInside < 0.0) firstInside = t;
      if (inside) {
        ASSERT_FALSE(r.intervals.empty());
        EXPECT_GE(t, r.intervals[0].begin - 1e-12);
        EXPECT_LE(t, r.intervals[0].end + 1e-12);
      }
    }
    if (firstInside >= 0.0) {
      ++hits;
      ASSERT_TRUE(r.hit());
      EXPECT_LE(r.fraction, firstInside + 1e-12);
      EXPECT_GE(r.fraction, firstInside - 1.0 / samples - 1e-12);
      EXPECT_NEAR(sphere.distance(p0 + r.fraction * (p1 - p0)) - sigma, r.state == SegmentState::Hit ? 0.0 : r.depth,
                  1e-9);
    }
  }
  EXPECT_GT(hits, 200);
}

}  // namespace
}  // namespace sdfccd
