/// @file
/// @brief PlaneField, SphereField, BoxField and CapsuleField: distances against brute force, closed-form
/// segment queries against hand-computed answers and dense sampling; the edge-case policy of segment_ccd.h
/// (touching, starting inside, zero length, FirstHit, NaN).
#include "sdfccd/field/analytic_fields.h"

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
  const auto r = intersectSegment(ground, Vec3(0.2, 3.0, 0.0), Vec3(1.0, -1.0, 0.5), allIntervals());
  EXPECT_EQ(r.state, SegmentState::Hit);
  EXPECT_DOUBLE_EQ(r.fraction, 0.75);
  ASSERT_EQ(r.intervals.size(), 1u);
  EXPECT_DOUBLE_EQ(r.intervals[0].begin, 0.75);
  EXPECT_DOUBLE_EQ(r.intervals[0].end, 1.0);
  EXPECT_TRUE(r.normal.isApprox(Vec3::UnitY()));
  EXPECT_DOUBLE_EQ(r.depth, 0.0);
  // With sigma = 1 the level set y = 1 is reached at t = 1/2.
  const auto s = intersectSegment(ground, Vec3(0.0, 3.0, 0.0), Vec3(0.0, -1.0, 0.0), allIntervals(1.0));
  EXPECT_DOUBLE_EQ(s.fraction, 0.5);
  // Moving up out of the ground: starts inside, leaves at t = 1/4.
  const auto u = intersectSegment(ground, Vec3(0.0, -1.0, 0.0), Vec3(0.0, 3.0, 0.0), allIntervals());
  EXPECT_EQ(u.state, SegmentState::StartsInside);
  EXPECT_DOUBLE_EQ(u.fraction, 0.0);
  EXPECT_DOUBLE_EQ(u.depth, -1.0);
  ASSERT_EQ(u.intervals.size(), 1u);
  EXPECT_DOUBLE_EQ(u.intervals[0].begin, 0.0);
  EXPECT_DOUBLE_EQ(u.intervals[0].end, 0.25);
  // Separated: both ends above.
  const auto v = intersectSegment(ground, Vec3(0.0, 1.0, 0.0), Vec3(5.0, 0.1, 0.0), allIntervals());
  EXPECT_EQ(v.state, SegmentState::Separated);
  EXPECT_DOUBLE_EQ(v.fraction, 1.0);
  EXPECT_TRUE(v.intervals.empty());
}

TEST(PlaneField, TouchingCountsZeroLengthIsAPointQueryFirstHitHasNoIntervals) {
  const PlaneField ground = PlaneField::ground();
  // Ends exactly on the plane: a hit at t = 1 with a degenerate interval.
  const auto touch = intersectSegment(ground, Vec3(0.0, 2.0, 0.0), Vec3(0.0, 0.0, 0.0), allIntervals());
  EXPECT_EQ(touch.state, SegmentState::Hit);
  EXPECT_DOUBLE_EQ(touch.fraction, 1.0);
  ASSERT_EQ(touch.intervals.size(), 1u);
  EXPECT_DOUBLE_EQ(touch.intervals[0].begin, 1.0);
  // Sliding along the plane: starts inside (touching), in contact all step.
  const auto slide = intersectSegment(ground, Vec3(0.0, 0.0, 0.0), Vec3(3.0, 0.0, 0.0), allIntervals());
  EXPECT_EQ(slide.state, SegmentState::StartsInside);
  EXPECT_DOUBLE_EQ(slide.intervals[0].end, 1.0);
  // Zero length.
  EXPECT_EQ(intersectSegment(ground, Vec3(1, 2, 3), Vec3(1, 2, 3), allIntervals()).state, SegmentState::Separated);
  const auto inside = intersectSegment(ground, Vec3(1, -2, 3), Vec3(1, -2, 3), allIntervals());
  EXPECT_EQ(inside.state, SegmentState::StartsInside);
  EXPECT_DOUBLE_EQ(inside.depth, -2.0);
  // FirstHit: no intervals.
  SegmentCcdSettings first;
  const auto f = intersectSegment(ground, Vec3(0.0, 1.0, 0.0), Vec3(0.0, -1.0, 0.0), first);
  EXPECT_EQ(f.state, SegmentState::Hit);
  EXPECT_DOUBLE_EQ(f.fraction, 0.5);
  EXPECT_TRUE(f.intervals.empty());
  // Non-finite input fails.
  EXPECT_EQ(intersectSegment(ground, Vec3(std::nan(""), 0, 0), Vec3::Zero(), first).state, SegmentState::Failed);
  SegmentCcdSettings nanSigma;
  nanSigma.sigma = std::nan("");
  EXPECT_EQ(intersectSegment(ground, Vec3::Zero(), Vec3::Ones(), nanSigma).state, SegmentState::Failed);
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
  const auto r = intersectSegment(sphere, Vec3(-3.0, 0.0, 0.0), Vec3(3.0, 0.0, 0.0), allIntervals());
  EXPECT_EQ(r.state, SegmentState::Hit);
  EXPECT_NEAR(r.fraction, 1.0 / 3.0, 1e-15);
  ASSERT_EQ(r.intervals.size(), 1u);
  EXPECT_NEAR(r.intervals[0].begin, 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(r.intervals[0].end, 2.0 / 3.0, 1e-15);
  EXPECT_TRUE(r.normal.isApprox(-Vec3::UnitX(), 1e-12));
  // sigma = 0.5: the level set is the sphere of radius 1.5; x in [-1.5, 1.5] is t in [1/4, 3/4].
  const auto s = intersectSegment(sphere, Vec3(-3.0, 0.0, 0.0), Vec3(3.0, 0.0, 0.0), allIntervals(0.5));
  EXPECT_NEAR(s.intervals[0].begin, 0.25, 1e-15);
  EXPECT_NEAR(s.intervals[0].end, 0.75, 1e-15);
  // Offset chord at height h = 0.6: half chord sqrt(1 - 0.36) = 0.8, so x in [-0.8, 0.8].
  const auto c = intersectSegment(sphere, Vec3(-2.0, 0.6, 0.0), Vec3(2.0, 0.6, 0.0), allIntervals());
  EXPECT_NEAR(c.intervals[0].begin, (2.0 - 0.8) / 4.0, 1e-15);
  EXPECT_NEAR(c.intervals[0].end, (2.0 + 0.8) / 4.0, 1e-15);
  // A miss.
  EXPECT_EQ(intersectSegment(sphere, Vec3(-2.0, 1.2, 0.0), Vec3(2.0, 1.2, 0.0), allIntervals()).state,
            SegmentState::Separated);
  // A segment that stops before reaching the sphere.
  EXPECT_EQ(intersectSegment(sphere, Vec3(-3.0, 0.0, 0.0), Vec3(-1.5, 0.0, 0.0), allIntervals()).state,
            SegmentState::Separated);
  // A level set below -r is empty.
  EXPECT_EQ(intersectSegment(sphere, Vec3(-3.0, 0.0, 0.0), Vec3(3.0, 0.0, 0.0), allIntervals(-1.5)).state,
            SegmentState::Separated);
}

TEST(SphereField, GrazingStartingInsideAndZeroLength) {
  const SphereField sphere(Vec3::Zero(), 1.0);
  // Tangent line y = 1: touches at x = 0 (t = 1/2); touching counts.
  const auto g = intersectSegment(sphere, Vec3(-1.0, 1.0, 0.0), Vec3(1.0, 1.0, 0.0), allIntervals());
  EXPECT_EQ(g.state, SegmentState::Hit);
  EXPECT_NEAR(g.fraction, 0.5, 1e-15);
  ASSERT_EQ(g.intervals.size(), 1u);
  EXPECT_NEAR(g.intervals[0].end - g.intervals[0].begin, 0.0, 1e-15);
  // Starting inside at the centre, leaving at x = 1 (t = 1/4).
  const auto in = intersectSegment(sphere, Vec3::Zero(), Vec3(4.0, 0.0, 0.0), allIntervals());
  EXPECT_EQ(in.state, SegmentState::StartsInside);
  EXPECT_DOUBLE_EQ(in.fraction, 0.0);
  EXPECT_DOUBLE_EQ(in.depth, -1.0);
  EXPECT_NEAR(in.intervals[0].end, 0.25, 1e-15);
  // Entirely inside.
  const auto all = intersectSegment(sphere, Vec3(-0.5, 0, 0), Vec3(0.5, 0, 0), allIntervals());
  EXPECT_EQ(all.state, SegmentState::StartsInside);
  EXPECT_DOUBLE_EQ(all.intervals[0].end, 1.0);
  // Zero length outside and inside.
  EXPECT_EQ(intersectSegment(sphere, Vec3(2, 0, 0), Vec3(2, 0, 0), allIntervals()).state, SegmentState::Separated);
  EXPECT_EQ(intersectSegment(sphere, Vec3(0.5, 0, 0), Vec3(0.5, 0, 0), allIntervals()).state,
            SegmentState::StartsInside);
  // Ending exactly on the sphere.
  const auto end = intersectSegment(sphere, Vec3(3, 0, 0), Vec3(1, 0, 0), allIntervals());
  EXPECT_EQ(end.state, SegmentState::Hit);
  EXPECT_DOUBLE_EQ(end.fraction, 1.0);
  EXPECT_EQ(intersectSegment(sphere, Vec3(std::nan(""), 0, 0), Vec3(1, 0, 0), allIntervals()).state,
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
    const auto r = intersectSegment(sphere, p0, p1, allIntervals(sigma));
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

// Dense sampling of phi along random segments (some axis-parallel, some in a face plane, some of zero
// length): the reported interval holds every inside sample, starts at the first one and ends at the last.
template <class Field>
int checkRandomSegments(const Field& field, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  int hits = 0;
  for (int n = 0; n < 1500; ++n) {
    const Vec3 p0(u(rng), u(rng), u(rng));
    Vec3 p1(u(rng), u(rng), u(rng));
    if (n % 5 == 1) p1[n % 3] = p0[n % 3];             // parallel to a coordinate plane
    if (n % 5 == 2) p1 = p0 + Vec3(0.0, u(rng), 0.0);  // along y
    if (n % 50 == 3) p1 = p0;                          // zero length
    const double sigma = n % 7 == 0 ? 0.0 : 0.3 * u(rng) / 3.0;
    const auto r = intersectSegment(field, p0, p1, allIntervals(sigma));
    EXPECT_LE(r.intervals.size(), 1u);  // convex: one interval at most
    const int samples = 3000;
    double firstInside = -1.0;
    double lastInside = -1.0;
    for (int k = 0; k <= samples; ++k) {
      const double t = static_cast<double>(k) / samples;
      if (field.distance(p0 + t * (p1 - p0)) > sigma) continue;
      if (firstInside < 0.0) firstInside = t;
      lastInside = t;
      if (r.intervals.empty()) {
        ADD_FAILURE() << "inside sample at t = " << t << " but no interval, segment " << n;
        return hits;
      }
      EXPECT_GE(t, r.intervals[0].begin - 1e-9) << "segment " << n;
      EXPECT_LE(t, r.intervals[0].end + 1e-9) << "segment " << n;
    }
    if (firstInside < 0.0) {
      // Possibly a contact shorter than the sampling step; then its ends are on the level set.
      if (r.hit()) {
        EXPECT_NEAR(field.distance(p0 + r.fraction * (p1 - p0)), sigma, 1e-9) << "segment " << n;
      }
      continue;
    }
    ++hits;
    EXPECT_TRUE(r.hit()) << "segment " << n;
    if (!r.hit()) continue;
    EXPECT_LE(r.fraction, firstInside + 1e-9);
    EXPECT_GE(r.fraction, firstInside - 1.0 / samples - 1e-9);
    EXPECT_LE(r.intervals[0].end, lastInside + 1.0 / samples + 1e-9);
    const double phiAtFraction = field.distance(p0 + r.fraction * (p1 - p0)) - sigma;
    EXPECT_NEAR(phiAtFraction, r.state == SegmentState::Hit ? 0.0 : r.depth, 1e-9) << "segment " << n;
  }
  return hits;
}

// The distance to a box surface by brute force: the nearest point of each face rectangle.
double bruteBoxDistance(const Vec3& h, const Vec3& p) {
  double nearest = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    for (double side : {-1.0, 1.0}) {
      Vec3 q = p.cwiseMax(-h).cwiseMin(h);
      q[axis] = side * h[axis];
      nearest = std::min(nearest, (p - q).norm());
    }
  }
  const bool inside = (p.cwiseAbs() - h).maxCoeff() <= 0.0;
  return inside ? -nearest : nearest;
}

TEST(BoxField, DistanceAndGradientMatchBruteForce) {
  const Vec3 h(1.0, 0.5, 1.5);
  const BoxField box(h);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int n = 0; n < 3000; ++n) {
    const Vec3 p(u(rng), u(rng), u(rng));
    EXPECT_NEAR(box.distance(p), bruteBoxDistance(h, p), 1e-12);
    // The gradient is the direction of steepest ascent: a small step along it raises phi by its length.
    const Vec3 g = box.gradient(p);
    EXPECT_NEAR(g.norm(), 1.0, 1e-12);
    EXPECT_NEAR(box.distance(p + 1e-7 * g) - box.distance(p), 1e-7, 1e-9);
  }
  EXPECT_DOUBLE_EQ(box.distance(Vec3(2.0, 0.0, 0.0)), 1.0);
  EXPECT_DOUBLE_EQ(box.distance(Vec3(0.0, 0.0, 0.0)), -0.5);
  EXPECT_DOUBLE_EQ(box.distance(Vec3(2.0, 1.5, 0.0)), std::sqrt(2.0));  // nearest point: the edge
  EXPECT_TRUE(box.gradient(Vec3(0.0, -0.25, 0.0)).isApprox(-Vec3::UnitY()));
  EXPECT_THROW(BoxField(Vec3(1.0, 0.0, 1.0)), Error);
  EXPECT_THROW(BoxField(Vec3(1.0, std::nan(""), 1.0)), Error);
}

TEST(BoxField, ClosedFormTimesAndEdgeCases) {
  const BoxField box(Vec3(1.0, 0.5, 1.5));
  // Along x through the centre: enters the face x = 1 at t = 0.25 (from x = 2 to -2), leaves at 0.75.
  const auto through = intersectSegment(box, Vec3(2, 0, 0), Vec3(-2, 0, 0), allIntervals());
  EXPECT_EQ(through.state, SegmentState::Hit);
  EXPECT_DOUBLE_EQ(through.fraction, 0.25);
  ASSERT_EQ(through.intervals.size(), 1u);
  EXPECT_DOUBLE_EQ(through.intervals[0].end, 0.75);
  EXPECT_TRUE(through.normal.isApprox(Vec3::UnitX()));
  // sigma = 0.5 near an edge: the rounded box. p(t) = (3 - 4t, 3 - 4t, 0) first meets the rounding of the edge
  // x = 1, y = 0.5: |(2 - 4t, 2.5 - 4t)| = 0.5 at 2 u^2 + u = 0 with u = 2 - 4t, so t = 1/2.
  const auto rounded = intersectSegment(box, Vec3(3, 3, 0), Vec3(-1, -1, 0), allIntervals(0.5));
  EXPECT_EQ(rounded.state, SegmentState::Hit);
  EXPECT_NEAR(rounded.fraction, 0.5, 1e-15);
  EXPECT_TRUE(rounded.normal.isApprox(Vec3(0, 1, 0)));
  // Sliding along the top face (touching counts): starts inside, in contact all step.
  const auto slide = intersectSegment(box, Vec3(-2, 0.5, 0), Vec3(2, 0.5, 0), allIntervals());
  EXPECT_EQ(slide.state, SegmentState::Hit);  // x = -2 is outside; touches the face from x = -1
  EXPECT_DOUBLE_EQ(slide.fraction, 0.25);
  EXPECT_DOUBLE_EQ(slide.intervals[0].end, 0.75);
  // Starting inside, sigma negative (an inner box).
  const auto inside = intersectSegment(box, Vec3(0, 0, 0), Vec3(0, 2, 0), allIntervals(-0.25));
  EXPECT_EQ(inside.state, SegmentState::StartsInside);
  EXPECT_DOUBLE_EQ(inside.depth, -0.25);
  EXPECT_DOUBLE_EQ(inside.intervals[0].end, 0.125);  // y <= 0.25
  // Zero length, FirstHit, NaN.
  EXPECT_EQ(intersectSegment(box, Vec3(5, 5, 5), Vec3(5, 5, 5), allIntervals()).state, SegmentState::Separated);
  EXPECT_EQ(intersectSegment(box, Vec3(0.5, 0, 0), Vec3(0.5, 0, 0), allIntervals()).state, SegmentState::StartsInside);
  SegmentCcdSettings first;
  first.mode = CcdMode::FirstHit;
  const auto firstHit = intersectSegment(box, Vec3(2, 0, 0), Vec3(-2, 0, 0), first);
  EXPECT_DOUBLE_EQ(firstHit.fraction, 0.25);
  EXPECT_TRUE(firstHit.intervals.empty());
  EXPECT_EQ(intersectSegment(box, Vec3(0, 0, 0), Vec3(std::nan(""), 0, 0), allIntervals()).state, SegmentState::Failed);
}

TEST(BoxField, RandomSegmentsMatchDenseSampling) {
  EXPECT_GT(checkRandomSegments(BoxField(Vec3(1.0, 0.5, 1.5)), 21), 300);
}

// The distance to a capsule by brute force: the nearest of many points along its axis segment.
double bruteCapsuleDistance(double radius, double halfHeight, int axis, const Vec3& p) {
  double nearest = std::numeric_limits<double>::infinity();
  const int samples = 20000;
  for (int k = 0; k <= samples; ++k) {
    Vec3 a = Vec3::Zero();
    a[axis] = -halfHeight + 2.0 * halfHeight * k / samples;
    nearest = std::min(nearest, (p - a).norm());
  }
  return nearest - radius;
}

TEST(CapsuleField, DistanceAndGradientMatchBruteForce) {
  for (int axis = 0; axis < 3; ++axis) {
    const CapsuleField capsule(0.6, 1.1, axis);
    std::mt19937 rng(7 + axis);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int n = 0; n < 300; ++n) {
      const Vec3 p(u(rng), u(rng), u(rng));
      // The sampled axis is at most 1.1e-4 from the true closest point: the distance is off by < 1e-8.
      EXPECT_NEAR(capsule.distance(p), bruteCapsuleDistance(0.6, 1.1, axis, p), 1e-8);
      const Vec3 g = capsule.gradient(p);
      EXPECT_NEAR(g.norm(), 1.0, 1e-12);
      EXPECT_NEAR(capsule.distance(p + 1e-7 * g) - capsule.distance(p), 1e-7, 1e-9);
    }
  }
  const CapsuleField y(0.5, 1.0);
  EXPECT_DOUBLE_EQ(y.distance(Vec3(0, 2.5, 0)), 1.0);   // above the top cap
  EXPECT_DOUBLE_EQ(y.distance(Vec3(2, 0.3, 0)), 1.5);   // beside the cylinder
  EXPECT_DOUBLE_EQ(y.distance(Vec3(0, 0.3, 0)), -0.5);  // on the axis
  EXPECT_TRUE(y.gradient(Vec3(0, 0.3, 0)).isZero(0.0));
  EXPECT_THROW(CapsuleField(0.0, 1.0), Error);
  EXPECT_THROW(CapsuleField(0.5, -1.0), Error);
  EXPECT_THROW(CapsuleField(0.5, 1.0, 3), Error);
}

TEST(CapsuleField, ClosedFormTimesAndEdgeCases) {
  const CapsuleField capsule(0.5, 1.0);  // axis y from -1 to 1
  // Down the axis from y = 3 to y = -3: enters the top cap at y = 1.5 (t = 0.25), leaves at y = -1.5 (0.75).
  const auto axial = intersectSegment(capsule, Vec3(0, 3, 0), Vec3(0, -3, 0), allIntervals());
  EXPECT_EQ(axial.state, SegmentState::Hit);
  EXPECT_DOUBLE_EQ(axial.fraction, 0.25);
  EXPECT_DOUBLE_EQ(axial.intervals[0].end, 0.75);
  EXPECT_TRUE(axial.normal.isApprox(Vec3::UnitY()));
  // Across the cylinder at y = 0.2 from x = 2 to x = -2: |x| <= 0.5 on [0.375, 0.625].
  const auto across = intersectSegment(capsule, Vec3(2, 0.2, 0), Vec3(-2, 0.2, 0), allIntervals());
  EXPECT_DOUBLE_EQ(across.fraction, 0.375);
  EXPECT_DOUBLE_EQ(across.intervals[0].end, 0.625);
  // With sigma = 0.5 the capsule grows to radius 1.
  EXPECT_DOUBLE_EQ(intersectSegment(capsule, Vec3(2, 0.2, 0), Vec3(-2, 0.2, 0), allIntervals(0.5)).fraction, 0.25);
  // A sigma below -radius: nothing is inside.
  EXPECT_EQ(intersectSegment(capsule, Vec3(0, 0, 0), Vec3(0, 0.1, 0), allIntervals(-0.6)).state,
            SegmentState::Separated);
  // A sphere when halfHeight = 0.
  const CapsuleField ball(0.5, 0.0);
  EXPECT_DOUBLE_EQ(intersectSegment(ball, Vec3(0, 2, 0), Vec3(0, -2, 0), allIntervals()).fraction, 0.375);
  EXPECT_EQ(intersectSegment(capsule, Vec3(0, 0, 0), Vec3(0, 0, std::nan("")), allIntervals()).state,
            SegmentState::Failed);
}

TEST(CapsuleField, RandomSegmentsMatchDenseSampling) {
  for (int axis = 0; axis < 3; ++axis) EXPECT_GT(checkRandomSegments(CapsuleField(0.6, 1.1, axis), 31 + axis), 200);
  EXPECT_GT(checkRandomSegments(CapsuleField(0.9, 0.0, 1), 40), 200);
}

}  // namespace
}  // namespace sdfccd
