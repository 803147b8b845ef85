/// @file
/// @brief cubicNonPositiveIntervals: known roots, grazing double roots, degenerate leading coefficients,
/// and random cubics against dense sampling.
#include "sdfccd/ccd/cubic_roots.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "sdfccd/math_types.h"

namespace sdfccd {
namespace {

std::vector<Interval> intervalsOf(const Cubic& g) {
  std::vector<Interval> out;
  cubicNonPositiveIntervals(g, [&](double a, double b) {
    out.push_back({a, b});
    return true;
  });
  return out;
}

// k (x - r1)(x - r2)(x - r3).
Cubic fromRoots(double k, double r1, double r2, double r3) {
  Cubic g;
  g.c3 = k;
  g.c2 = -k * (r1 + r2 + r3);
  g.c1 = k * (r1 * r2 + r1 * r3 + r2 * r3);
  g.c0 = -k * r1 * r2 * r3;
  return g;
}

TEST(CubicRoots, QuadraticRootsInUnitAreSortedAndStable) {
  double r[2];
  ASSERT_EQ(quadraticRootsInUnit(1.0, -1.0, 0.21, r), 2);  // roots 0.3, 0.7
  EXPECT_NEAR(r[0], 0.3, 1e-15);
  EXPECT_NEAR(r[1], 0.7, 1e-15);
  ASSERT_EQ(quadraticRootsInUnit(0.0, 2.0, -1.0, r), 1);  // linear
  EXPECT_EQ(r[0], 0.5);
  EXPECT_EQ(quadraticRootsInUnit(0.0, 0.0, 1.0, r), 0);
  EXPECT_EQ(quadraticRootsInUnit(1.0, 0.0, 1.0, r), 0);  // complex
  // Tiny leading coefficient: the root near 0.25 of 1e-20 x^2 + 4 x - 1 keeps full precision.
  ASSERT_EQ(quadraticRootsInUnit(1e-20, 4.0, -1.0, r), 1);
  EXPECT_NEAR(r[0], 0.25, 1e-16);
}

TEST(CubicRoots, ThreeSimpleRootsGiveTwoIntervals) {
  const auto iv = intervalsOf(fromRoots(1.0, 0.2, 0.5, 0.9));  // <= 0 on [0, 0.2] and [0.5, 0.9]
  ASSERT_EQ(iv.size(), 2u);
  EXPECT_EQ(iv[0].begin, 0.0);
  EXPECT_NEAR(iv[0].end, 0.2, 1e-15);
  EXPECT_NEAR(iv[1].begin, 0.5, 1e-15);
  EXPECT_NEAR(iv[1].end, 0.9, 1e-15);
  const auto neg = intervalsOf(fromRoots(-1.0, 0.2, 0.5, 0.9));  // <= 0 on [0.2, 0.5] and [0.9, 1]
  ASSERT_EQ(neg.size(), 2u);
  EXPECT_NEAR(neg[0].begin, 0.2, 1e-15);
  EXPECT_NEAR(neg[0].end, 0.5, 1e-15);
  EXPECT_NEAR(neg[1].begin, 0.9, 1e-15);
  EXPECT_EQ(neg[1].end, 1.0);
}

TEST(CubicRoots, EndpointsAreInContact) {
  // The reported ends evaluate to <= 0 (the answer errs on the side of contact).
  for (double k : {1.0, -1.0, 1e-6, 1e6}) {
    const Cubic g = fromRoots(k, 0.123456789, 0.5, 0.87654321);
    for (const auto& iv : intervalsOf(g)) {
      EXPECT_LE(g(iv.begin), 0.0);
      EXPECT_LE(g(iv.end), 0.0);
    }
  }
}

TEST(CubicRoots, GrazingDoubleRootTouchesAndCounts) {
  // (x - 0.5)^2 (x + 2) >= 0 on [0, 1], zero only at 0.5 (exact in binary).
  const auto iv = intervalsOf(fromRoots(1.0, 0.5, 0.5, -2.0));
  ASSERT_EQ(iv.size(), 1u);
  // Near a double root the evaluated cubic is rounding noise over a width ~sqrt(eps): a tiny interval.
  EXPECT_NEAR(iv[0].begin, 0.5, 1e-7);
  EXPECT_NEAR(iv[0].end, 0.5, 1e-7);
  // Lifted slightly: no contact.
  Cubic lifted = fromRoots(1.0, 0.5, 0.5, -2.0);
  lifted.c0 += 1e-12;
  EXPECT_TRUE(intervalsOf(lifted).empty());
  // Lowered slightly: a short interval around 0.5.
  Cubic lowered = fromRoots(1.0, 0.5, 0.5, -2.0);
  lowered.c0 -= 1e-12;
  const auto low = intervalsOf(lowered);
  ASSERT_EQ(low.size(), 1u);
  EXPECT_LT(low[0].begin, 0.5);
  EXPECT_GT(low[0].end, 0.5);
  EXPECT_LT(low[0].end - low[0].begin, 1e-5);
}

TEST(CubicRoots, TripleRootAndRootsAtTheEnds) {
  const auto triple = intervalsOf(fromRoots(1.0, 0.3, 0.3, 0.3));  // <= 0 on [0, 0.3]
  ASSERT_EQ(triple.size(), 1u);
  EXPECT_EQ(triple[0].begin, 0.0);
  EXPECT_NEAR(triple[0].end, 0.3, 1e-5);                          // a triple root is ill-conditioned: ~cbrt(eps)
  const auto ends = intervalsOf(fromRoots(-1.0, 0.0, 1.0, 3.0));  // -x (x-1)(x-3): <= 0 on [0, 1]? sign check
  // At x = 0.5: -0.5 * -0.5 * -2.5 = -0.625 <= 0, and zero at both ends.
  ASSERT_EQ(ends.size(), 1u);
  EXPECT_EQ(ends[0].begin, 0.0);
  EXPECT_EQ(ends[0].end, 1.0);
  const auto touchEnds = intervalsOf(fromRoots(1.0, 0.0, 1.0, 3.0));  // >= 0 inside, zero at 0 and 1
  ASSERT_EQ(touchEnds.size(), 2u);
  EXPECT_EQ(touchEnds[0].begin, 0.0);
  EXPECT_EQ(touchEnds[0].end, 0.0);
  EXPECT_EQ(touchEnds[1].begin, 1.0);
  EXPECT_EQ(touchEnds[1].end, 1.0);
}

TEST(CubicRoots, DegenerateLeadingCoefficients) {
  Cubic quadratic;  // (x - 0.25)(x - 0.75)
  quadratic.c2 = 1.0;
  quadratic.c1 = -1.0;
  quadratic.c0 = 0.1875;
  auto iv = intervalsOf(quadratic);
  ASSERT_EQ(iv.size(), 1u);
  EXPECT_NEAR(iv[0].begin, 0.25, 1e-15);
  EXPECT_NEAR(iv[0].end, 0.75, 1e-15);
  quadratic.c3 = 1e-20;  // nearly a quadratic
  iv = intervalsOf(quadratic);
  ASSERT_EQ(iv.size(), 1u);
  EXPECT_NEAR(iv[0].begin, 0.25, 1e-15);
  EXPECT_NEAR(iv[0].end, 0.75, 1e-15);
  Cubic linear;
  linear.c1 = -2.0;
  linear.c0 = 1.0;
  iv = intervalsOf(linear);
  ASSERT_EQ(iv.size(), 1u);
  EXPECT_EQ(iv[0].begin, 0.5);
  EXPECT_EQ(iv[0].end, 1.0);
  Cubic zero;  // phi == sigma along the whole cell: touching everywhere
  iv = intervalsOf(zero);
  ASSERT_EQ(iv.size(), 1u);
  EXPECT_EQ(iv[0].begin, 0.0);
  EXPECT_EQ(iv[0].end, 1.0);
  Cubic positive;
  positive.c0 = 1e-300;
  EXPECT_TRUE(intervalsOf(positive).empty());
}

TEST(CubicRoots, RandomCubicsMatchDenseSampling) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> r(-0.2, 1.2);
  const int samples = 20001;
  for (int n = 0; n < 2000; ++n) {
    // Half with roots placed in the unit interval, half with random coefficients.
    const Cubic g = n % 2 == 0 ? fromRoots(u(rng), r(rng), r(rng), r(rng)) : Cubic{u(rng), u(rng), u(rng), u(rng)};
    const auto iv = intervalsOf(g);
    for (std::size_t k = 1; k < iv.size(); ++k) ASSERT_LT(iv[k - 1].end, iv[k].begin);
    for (int s = 0; s < samples; ++s) {
      const double x = static_cast<double>(s) / (samples - 1);
      const double gx = g(x);
      bool inside = false;
      for (const auto& i : iv) inside = inside || (x >= i.begin - 1e-9 && x <= i.end + 1e-9);
      if (gx < -1e-9) {
        ASSERT_TRUE(inside) << "n=" << n << " x=" << x << " g=" << gx;
      }
      bool strictlyInside = false;
      for (const auto& i : iv) strictlyInside = strictlyInside || (x > i.begin + 1e-9 && x < i.end - 1e-9);
      if (gx > 1e-9) {
        ASSERT_FALSE(strictlyInside) << "n=" << n << " x=" << x << " g=" << gx;
      }
    }
  }
}

TEST(CubicRoots, FirstHitStopsAtTheFirstInterval) {
  int calls = 0;
  double first = -1.0;
  cubicNonPositiveIntervals(fromRoots(1.0, 0.2, 0.5, 0.9), [&](double a, double) {
    ++calls;
    first = a;
    return false;
  });
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(first, 0.0);
}

}  // namespace
}  // namespace sdfccd
