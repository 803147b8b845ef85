/// @file
/// @brief GridField::intersectSegment on segments far longer than the field: the segment is clipped to the box in
/// double-double before the walk, so a 1e20-long segment reports the contact the short segment on the same line
/// reports. Without the clip, t would have no resolution left for the box and every such query would answer "no
/// hit".
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/segment_reference.h"
#include "sdfccd/field/grid_field.h"

namespace sdfccd {
namespace {

SegmentCcdSettings settingsOf(CcdMode mode, double sigma = 0.0) {
  SegmentCcdSettings s;
  s.sigma = sigma;
  s.mode = mode;
  return s;
}

SegmentCcdResult query(const GridField& field, const Vec3& p0, const Vec3& p1, CcdMode mode, double sigma = 0.0) {
  SegmentCcdResult r;
  field.intersectSegment(p0, p1, settingsOf(mode, sigma), r);
  return r;
}

// The long segment (p0, p1) and the short one (s0, s1) lie on the same line (to ~1e-15 of a unit) and enter
// the contact set at the same point: same state, hit point within 1/100 of a cell, same normal, and a
// fraction that is the hit point's parameter up to double rounding of t.
void expectSameHit(const GridField& field, const Vec3& p0, const Vec3& p1, const Vec3& s0, const Vec3& s1,
                   double sigma = 0.0) {
  SCOPED_TRACE(::testing::Message() << "long " << p0.transpose() << " -> " << p1.transpose());
  const double cell = field.spacing();
  const SegmentCcdResult shortHit = query(field, s0, s1, CcdMode::FirstHit, sigma);
  ASSERT_EQ(shortHit.state, SegmentState::Hit);
  for (const CcdMode mode : {CcdMode::FirstHit, CcdMode::AllIntervals}) {
    const SegmentCcdResult longHit = query(field, p0, p1, mode, sigma);
    ASSERT_EQ(longHit.state, SegmentState::Hit);
    EXPECT_LT((longHit.point - shortHit.point).norm(), 0.01 * cell);
    EXPECT_LT((longHit.normal - shortHit.normal).norm(), 1e-6);
    EXPECT_GT(longHit.fraction, 0.0);
    EXPECT_LE(longHit.fraction, 1.0);
    // The fraction is rounded to double: p0 + t (p1 - p0) is within a few ulps of t times the length.
    const double length = (p1 - p0).norm();
    const Vec3 fromFraction = p0 + longHit.fraction * (p1 - p0);
    EXPECT_LT((fromFraction - shortHit.point).norm(), 4.0 * 2.3e-16 * length + 2.0 * cell);
    if (mode == CcdMode::AllIntervals) {
      ASSERT_FALSE(longHit.intervals.empty());
      EXPECT_EQ(longHit.intervals[0].begin, longHit.fraction);
    }
  }
}

std::shared_ptr<const SdfGrid> sphereGrid(const Vec3& origin, const Vec3& centre, double radius) {
  const double h = 1.0 / 16.0;
  return test::sampleGrid({33, 33, 33}, origin, h, [&](const Vec3& p) { return (p - centre).norm() - radius; });
}

TEST(LongSegment, TenToTheTwentyLongSegmentReportsTheShortSegmentsHit) {
  const GridField field(sphereGrid(Vec3(-1, -1, -1), Vec3::Zero(), 0.6));
  // Both ends 1e20 away, on a line through the origin (exact: the ends are -L d and L d with d dyadic).
  const double L = std::ldexp(1.0, 66);  // 7.4e19 each way: 1.5e20 long
  for (const Vec3& d : {Vec3(1.0, 0.5, 0.25), Vec3(-0.375, 1.0, 0.125), Vec3(0.5, -0.5, 1.0)}) {
    expectSameHit(field, -L * d, L * d, -2.0 * d, 2.0 * d);
  }
  // One end near the field, the other 1e20 away (and the reverse), along random directions: the line is the
  // near end plus multiples of the rounded direction.
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n = 0; n < 50; ++n) {
    const Vec3 target(0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng));
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 nearEnd = target + 1.5 * dir;  // beyond the sphere, inside the box or just outside
    const Vec3 farEnd = nearEnd - 1e20 * dir;
    const Vec3 along = (nearEnd - farEnd).normalized();
    expectSameHit(field, farEnd, nearEnd, nearEnd - 3.0 * along, nearEnd);
    const Vec3 otherNear = target - 1.5 * dir;  // the far end beyond the field on the other side
    const Vec3 otherFar = otherNear + 1e20 * dir;
    const Vec3 back = (otherFar - otherNear).normalized();
    expectSameHit(field, otherNear, otherFar, otherNear, otherNear + 3.0 * back);
  }
}

TEST(LongSegment, GridAlignedLongSegmentsAlongAxesAndThroughNodes) {
  const GridField field(sphereGrid(Vec3(-1, -1, -1), Vec3::Zero(), 0.6));
  // Along each axis, through grid nodes (offsets multiples of the spacing) and between them.
  for (const double offset : {0.0, 0.125, 0.1, -0.3}) {
    for (int a = 0; a < 3; ++a) {
      Vec3 p0 = Vec3::Constant(offset), p1 = Vec3::Constant(offset);
      p0[a] = -1e20;
      p1[a] = 1e20;
      Vec3 s0 = p0, s1 = p1;
      s0[a] = -2.0;
      s1[a] = 2.0;
      expectSameHit(field, p0, p1, s0, s1);
      expectSameHit(field, p1, p0, s1, s0);
    }
  }
  // A long segment that starts inside the field and inside the sphere starts inside.
  const SegmentCcdResult inside = query(field, Vec3::Zero(), Vec3(1e20, 0, 0), CcdMode::FirstHit);
  EXPECT_EQ(inside.state, SegmentState::StartsInside);
  EXPECT_EQ(inside.fraction, 0.0);
  EXPECT_LT(inside.depth, -0.5);
  // A long segment beside the field is outside it; one pointing away from it never reaches it.
  EXPECT_EQ(query(field, Vec3(-1e20, 1.5, 0), Vec3(1e20, 1.5, 0), CcdMode::FirstHit).state, SegmentState::OutsideField);
  EXPECT_EQ(query(field, Vec3(2, 0, 0), Vec3(1e20, 0, 0), CcdMode::FirstHit).state, SegmentState::OutsideField);
}

TEST(LongSegment, FieldFarFromTheOriginLongSegments) {
  const Vec3 origin(1000.0, -2000.0, 3000.0);
  const Vec3 centre = origin + Vec3(1.0, 1.0, 1.0);
  const GridField field(sphereGrid(origin, centre, 0.5));
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n = 0; n < 50; ++n) {
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 nearEnd = centre + Vec3(0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng)) + 1.2 * dir;
    const Vec3 farEnd = nearEnd - 1e20 * dir;
    const Vec3 along = (nearEnd - farEnd).normalized();
    expectSameHit(field, farEnd, nearEnd, nearEnd - 2.5 * along, nearEnd);
  }
  // Grid-aligned, far from the origin: x from -1e20 to 1e20 through the centre's row.
  const Vec3 row = centre + Vec3(0.0, 0.0625, -0.125);
  expectSameHit(field, Vec3(-1e20, row.y(), row.z()), Vec3(1e20, row.y(), row.z()), row - Vec3(2, 0, 0),
                row + Vec3(2, 0, 0));
}

TEST(LongSegment, MaxFractionAppliesToTheMappedFraction) {
  const GridField field(sphereGrid(Vec3(-1, -1, -1), Vec3::Zero(), 0.6));
  const Vec3 p0(-1e20, 0.0, 0.0), p1(1e20, 0.0, 0.0);
  const SegmentCcdResult full = query(field, p0, p1, CcdMode::FirstHit);
  ASSERT_EQ(full.state, SegmentState::Hit);
  SegmentCcdSettings s = settingsOf(CcdMode::FirstHit);
  SegmentCcdResult r;
  s.maxFraction = 0.25;  // before the field
  field.intersectSegment(p0, p1, s, r);
  EXPECT_EQ(r.state, SegmentState::Separated);
  s.maxFraction = 0.75;  // after it
  field.intersectSegment(p0, p1, s, r);
  EXPECT_EQ(r.state, SegmentState::Hit);
  EXPECT_EQ(r.fraction, full.fraction);
}

}  // namespace
}  // namespace sdfccd
