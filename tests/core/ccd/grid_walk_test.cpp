/// @file
/// @brief GridWalk (3D DDA): contiguous cell t-ranges, each cell holding its part of the segment, against
/// the cells found by sorting every grid-plane crossing; degenerate directions; jumpTo consistency.
#include "sdfccd/ccd/grid_walk.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace sdfccd {
namespace {

struct Visit {
  Vec3i cell;
  double tIn, tOut;
};

std::vector<Visit> walkAll(GridWalk walk) {
  std::vector<Visit> visits;
  do {
    visits.push_back({walk.cell(), walk.cellBegin(), walk.cellEnd()});
  } while (walk.next());
  return visits;
}

// Clip of u0 + t d to [0, cells] (test's own slab clip).
bool clip(const Vec3& u0, const Vec3& d, const Vec3i& cells, double& t0, double& t1) {
  t0 = 0.0;
  t1 = 1.0;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (u0[a] < 0.0 || u0[a] > cells[a]) return false;
      continue;
    }
    double lo = -u0[a] / d[a], hi = (cells[a] - u0[a]) / d[a];
    if (lo > hi) std::swap(lo, hi);
    t0 = std::max(t0, lo);
    t1 = std::min(t1, hi);
  }
  return t0 < t1;
}

void checkWalk(const Vec3& u0, const Vec3& d, const Vec3i& cells) {
  double t0, t1;
  if (!clip(u0, d, cells, t0, t1)) return;
  const auto visits = walkAll(GridWalk(u0, d, cells, t0, t1));
  ASSERT_FALSE(visits.empty());
  EXPECT_EQ(visits.front().tIn, t0);
  EXPECT_NEAR(visits.back().tOut, t1, 1e-12);
  // Brute force: every plane crossing inside (t0, t1), sorted; each gap is one cell.
  std::vector<double> ts = {t0, t1};
  for (int a = 0; a < 3; ++a)
    if (d[a] != 0.0)
      for (int k = 0; k <= cells[a]; ++k) {
        const double t = (k - u0[a]) / d[a];
        if (t > t0 && t < t1) ts.push_back(t);
      }
  std::sort(ts.begin(), ts.end());
  std::vector<Vec3i> expected;
  for (std::size_t n = 1; n < ts.size(); ++n) {
    if (ts[n] - ts[n - 1] < 1e-12) continue;
    const Vec3 u = u0 + 0.5 * (ts[n] + ts[n - 1]) * d;
    Vec3i c;
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor(u[a])), 0, cells[a] - 1);
    expected.push_back(c);
  }
  std::vector<Vec3i> got;
  for (std::size_t n = 0; n < visits.size(); ++n) {
    if (n > 0) {
      ASSERT_EQ(visits[n].tIn, visits[n - 1].tOut);  // contiguous
    }
    ASSERT_LE(visits[n].tIn, visits[n].tOut);
    if (visits[n].tOut - visits[n].tIn < 1e-12) continue;
    got.push_back(visits[n].cell);
  }
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t n = 0; n < got.size(); ++n) ASSERT_EQ(got[n], expected[n]) << n;
}

TEST(GridWalk, RandomSegmentsVisitTheCellsOfTheSortedPlaneCrossings) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 12.0);
  const Vec3i cells(10, 7, 9);
  for (int n = 0; n < 3000; ++n) {
    const Vec3 u0(u(rng), u(rng), u(rng)), u1(u(rng), u(rng), u(rng));
    checkWalk(u0, u1 - u0, cells);
  }
}

TEST(GridWalk, DegenerateDirectionsAndVertices) {
  const Vec3i cells(8, 8, 8);
  checkWalk(Vec3(0, 0, 0), Vec3(8, 8, 8), cells);       // through every vertex on the diagonal
  checkWalk(Vec3(8, 8, 8), Vec3(-8, -8, -8), cells);    // backwards
  checkWalk(Vec3(3, 4, 0), Vec3(0, 0, 8), cells);       // along a grid line
  checkWalk(Vec3(3, 0.5, 0), Vec3(0, 7, 8), cells);     // in a grid plane
  checkWalk(Vec3(8, 8, 0.5), Vec3(0, -8, 7), cells);    // on the box's far faces
  checkWalk(Vec3(0, 0, 0), Vec3(8, 4, 2), cells);       // through every other vertex
  checkWalk(Vec3(1, 2, 3), Vec3(1e-310, 4, 2), cells);  // 1/d overflows: treated as not moving
  // Zero length: one cell, zero-length range.
  const auto one = walkAll(GridWalk(Vec3(2.5, 3, 4), Vec3::Zero(), cells, 0.0, 1.0));
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].cell, Vec3i(2, 3, 4));
}

TEST(GridWalk, JumpToContinuesWithIdenticalCellRanges) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(0.0, 16.0);
  const Vec3i cells(16, 16, 16);
  for (int n = 0; n < 500; ++n) {
    const Vec3 u0(u(rng), u(rng), u(rng)), u1(u(rng), u(rng), u(rng));
    const auto all = walkAll(GridWalk(u0, u1 - u0, cells, 0.0, 1.0));
    // Jump to the start of a random positive-length visit: the remaining visits agree.
    std::size_t k = static_cast<std::size_t>(n) % all.size();
    while (k < all.size() && all[k].tOut <= all[k].tIn) ++k;
    if (k >= all.size()) continue;
    GridWalk walk(u0, u1 - u0, cells, 0.0, 1.0);
    walk.jumpTo(all[k].tIn);
    const auto rest = walkAll(walk);
    std::vector<Visit> a, b;
    for (std::size_t m = k; m < all.size(); ++m)
      if (all[m].tOut > all[m].tIn) a.push_back(all[m]);
    for (const auto& v : rest)
      if (v.tOut > v.tIn) b.push_back(v);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t m = 0; m < a.size(); ++m) {
      ASSERT_EQ(a[m].cell, b[m].cell);
      ASSERT_EQ(a[m].tIn, b[m].tIn);
      ASSERT_EQ(a[m].tOut, b[m].tOut);
    }
  }
}

}  // namespace
}  // namespace sdfccd
