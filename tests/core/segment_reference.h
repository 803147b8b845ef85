/// @file
/// @brief Test helpers for the segment CCD: fields made in the tests and a brute-force reference that
/// samples the trilinear field densely along a segment (independent of the library's walk and cubic).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "sdfccd/field/grid_field.h"
#include "sdfccd/field/sdf_grid.h"

namespace sdfccd::test {

/// A grid sampling f at its nodes.
inline std::shared_ptr<const SdfGrid> sampleGrid(const Vec3i& nodes, const Vec3& origin, double spacing,
                                                 const std::function<double(const Vec3&)>& f) {
  std::vector<float> v;
  v.reserve(static_cast<std::size_t>(nodes.prod()));
  for (int k = 0; k < nodes.z(); ++k)
    for (int j = 0; j < nodes.y(); ++j)
      for (int i = 0; i < nodes.x(); ++i) v.push_back(static_cast<float>(f(origin + spacing * Vec3(i, j, k))));
  return std::make_shared<SdfGrid>(nodes, origin, spacing, std::move(v));
}

/// A grid of independent random values in [lo, hi]: many roots per cell along a segment.
inline std::shared_ptr<const SdfGrid> randomGrid(const Vec3i& nodes, const Vec3& origin, double spacing,
                                                 std::uint32_t seed, double lo = -1.0, double hi = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<float> v(static_cast<std::size_t>(nodes.prod()));
  for (auto& x : v) x = static_cast<float>(u(rng));
  return std::make_shared<SdfGrid>(nodes, origin, spacing, std::move(v));
}

/// phi along the segment by pointwise trilinear interpolation; +inf outside the closed box.
inline double phiAlong(const SdfGrid& grid, const Vec3& p0, const Vec3& p1, double t) {
  const Vec3 p = p0 + t * (p1 - p0);
  // A slightly tolerant box test: the library clips in index coordinates.
  const Vec3 u = (p - grid.origin()) / grid.spacing();
  const Vec3 cells = grid.cellCounts().cast<double>();
  if ((u.array() < -1e-12).any() || (u.array() > cells.array() + 1e-12).any()) return INFINITY;
  return grid.interpolate(p);
}

/// Checks a result against dense sampling: no sample clearly in contact is left out, no sample clearly
/// free is reported, interval ends lie on the level set (or at 0, 1, the box), the first hit is the first.
/// `tolPhi`: model units; `tolT`: fraction of the step.
inline ::testing::AssertionResult matchesBruteForce(const SdfGrid& grid, const Vec3& p0, const Vec3& p1, double sigma,
                                                    const SegmentCcdResult& all, int samples = 20000,
                                                    double tolPhi = 1e-7, double tolT = 1e-9) {
  std::ostringstream why;
  auto covered = [&](double t, double slack) {
    for (std::size_t n = 0; n < all.intervals.size(); ++n)
      if (t >= all.intervals[n].begin - slack && t <= all.intervals[n].end + slack) return true;
    return false;
  };
  double firstClear = 2.0;
  for (int s = 0; s < samples; ++s) {
    const double t = static_cast<double>(s) / (samples - 1);
    const double g = phiAlong(grid, p0, p1, t) - sigma;
    if (g < -tolPhi) {
      if (firstClear > 1.0) firstClear = t;
      if (!covered(t, tolT)) {
        why << "sample t=" << t << " has phi-sigma=" << g << " but is not in an interval";
        return ::testing::AssertionFailure() << why.str();
      }
    } else if (g > tolPhi) {
      if (covered(t, -tolT)) {
        why << "sample t=" << t << " has phi-sigma=" << g << " but lies in an interval";
        return ::testing::AssertionFailure() << why.str();
      }
    }
  }
  for (std::size_t n = 0; n < all.intervals.size(); ++n) {
    const Interval& iv = all.intervals[n];
    if (!(iv.begin <= iv.end) || iv.begin < 0.0 || iv.end > 1.0)
      return ::testing::AssertionFailure() << "bad interval " << iv.begin << ":" << iv.end;
    if (n > 0 && !(all.intervals[n - 1].end < iv.begin))
      return ::testing::AssertionFailure() << "intervals not sorted/disjoint at " << n;
    for (double t : {iv.begin, iv.end}) {
      const double g = phiAlong(grid, p0, p1, t) - sigma;
      // Interior ends are crossings; ends at 0, 1 or the box face are in contact.
      if (g > tolPhi) return ::testing::AssertionFailure() << "interval end t=" << t << " has phi-sigma=" << g;
    }
  }
  if (firstClear <= 1.0) {
    if (!all.hit()) return ::testing::AssertionFailure() << "missed contact at t=" << firstClear;
    if (all.fraction > firstClear + tolT)
      return ::testing::AssertionFailure() << "first hit " << all.fraction << " after sample " << firstClear;
  }
  if (all.hit()) {
    if (all.intervals.empty() || all.fraction != all.intervals[0].begin)
      return ::testing::AssertionFailure() << "fraction is not the first interval's begin";
  }
  return ::testing::AssertionSuccess();
}

inline std::string describe(const Vec3& p0, const Vec3& p1, double sigma) {
  std::ostringstream s;
  s.precision(17);
  s << "p0=(" << p0.transpose() << ") p1=(" << p1.transpose() << ") sigma=" << sigma;
  return s.str();
}

}  // namespace sdfccd::test
