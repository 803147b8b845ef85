/// @file
/// @brief The templated cell walk of the segment CCD: DDA + octree skipping + per-cell root finding
/// (paper Sections 3.1 and 3.2). Private to grid_field.cpp.
///
/// @details The method (exact cubic / eq. (2) regula falsi), the mode (first hit / all intervals) and the
/// octree mode (full / leaves / off) are template parameters, so the per-cell loop has no virtual call and
/// no branch on settings; grid_field.cpp instantiates the twelve combinations once.
///
/// Why the three octree modes give identical answers: a block (or cell) is skipped only when its minimum
/// exceeds sigma, and the walk never evaluates the field outside the current cell (local coordinates are
/// clamped to [0,1]^3, where trilinear interpolation is a convex combination of the corners), so phi > sigma
/// on every skipped part; and the cells that are visited get bit-identical t-ranges in every mode (GridWalk
/// computes crossing times by one formula and jumpTo re-enters the walk consistently).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "sdfccd/ccd/cell_cubic.h"
#include "sdfccd/ccd/cubic_roots.h"
#include "sdfccd/ccd/grid_walk.h"
#include "sdfccd/ccd/segment_ccd.h"
#include "sdfccd/field/min_distance_octree.h"
#include "sdfccd/tolerances.h"

namespace sdfccd::detail {

/// Regula falsi iterations of the bisection method (the paper uses 5).
constexpr int kBisectionIterations = 5;

/// Everything the walk reads, gathered once per query.
struct WalkContext {
  const float* values = nullptr;  ///< grid values, i fastest
  std::size_t strideY = 0;        ///< nodes per row
  std::size_t strideZ = 0;        ///< nodes per slice
  const MinDistanceOctree* octree = nullptr;
  double sigma = 0.0;
};

/// What the walk found.
struct WalkOutput {
  bool found = false;  ///< a contact was found
  double first = 1.0;  ///< the first contact t (valid when found)
};

inline void appendMerged(IntervalList& list, double begin, double end) {
  if (!list.empty() && begin <= list.back().end + tolerance::kIntervalMergeGap) {
    if (end > list.back().end) list.back().end = end;
    return;
  }
  list.append(begin, end);
}

inline int highestBit(unsigned x) {
  // x > 0. (std::bit_width is C++20.)
  return 31 - __builtin_clz(x);
}

/// Walks the cells of `walk` and reports contacts in `out` (first hit) and `intervals` (all intervals).
/// `pointOnly`: the clipped segment is a single point (visit its cell once).
template <CcdMethod kMethod, CcdMode kMode, OctreeMode kOctree>
void walkSegment(const WalkContext& ctx, GridWalk& walk, bool pointOnly, WalkOutput& out, IntervalList& intervals) {
  const double sigma = ctx.sigma;
  const MinDistanceOctree& octree = *ctx.octree;
  const int topLevel = octree.topLevel();
  // Full mode: octree levels above `checkFrom` are known not to be skippable for the current cell.
  Vec3i lastChecked(0, 0, 0);
  bool haveChecked = false;

  for (;;) {
    const double tIn = walk.cellBegin();
    const double tOut = walk.cellEnd();
    if (tOut <= tIn && !pointOnly) {  // a zero-length cell (an edge or a vertex crossing): its point is shared
      if (!walk.next()) break;
      continue;
    }
    const Vec3i cell = walk.cell();

    if constexpr (kOctree == OctreeMode::Full) {
      int checkFrom = topLevel;
      if (haveChecked) {
        const unsigned diff = static_cast<unsigned>((cell.x() ^ lastChecked.x()) | (cell.y() ^ lastChecked.y()) |
                                                    (cell.z() ^ lastChecked.z()));
        checkFrom = diff == 0 ? 0 : std::min(topLevel, highestBit(diff));
      }
      lastChecked = cell;
      haveChecked = true;
      int skipLevel = 0;
      // From the coarsest changed level down: the first block whose minimum exceeds sigma is the largest.
      for (int level = checkFrom; level >= 1; --level) {
        if (octree.blockMinAtCell(level, cell) > sigma) {
          skipLevel = level;
          break;
        }
      }
      if (skipLevel > 0) {
        const Vec3i lo(cell.x() >> skipLevel << skipLevel, cell.y() >> skipLevel << skipLevel,
                       cell.z() >> skipLevel << skipLevel);
        const Vec3i hi = lo.array() + ((1 << skipLevel) - 1);
        const double tExit = walk.exitTimeOfBlock(lo, hi);
        if (!(tExit < walk.end()) || pointOnly) break;
        walk.jumpTo(tExit);
        const Vec3i& next = walk.cell();
        if ((next.x() >> skipLevel) == (cell.x() >> skipLevel) && (next.y() >> skipLevel) == (cell.y() >> skipLevel) &&
            (next.z() >> skipLevel) == (cell.z() >> skipLevel)) {
          break;  // the block reaches the box's face: the segment leaves the box through it
        }
        continue;
      }
    }

    const float* base = ctx.values + static_cast<std::size_t>(cell.x()) +
                        ctx.strideY * static_cast<std::size_t>(cell.y()) +
                        ctx.strideZ * static_cast<std::size_t>(cell.z());
    const std::size_t sy = ctx.strideY, sz = ctx.strideZ;
    const double c[8] = {base[0],  base[1],      base[sy],      base[sy + 1],
                         base[sz], base[sz + 1], base[sz + sy], base[sz + sy + 1]};
    if constexpr (kOctree != OctreeMode::Off) {
      const double cellMin = std::min(std::min(std::min(c[0], c[1]), std::min(c[2], c[3])),
                                      std::min(std::min(c[4], c[5]), std::min(c[6], c[7])));
      if (cellMin > sigma) {
        if (!walk.next()) break;
        continue;
      }
    }

    const Vec3 wIn = walk.local(tIn);
    const Vec3 wOut = walk.local(tOut);
    auto toT = [tIn, tOut](double beta) {
      if (beta <= 0.0) return tIn;
      if (beta >= 1.0) return tOut;
      return std::clamp(tIn + beta * (tOut - tIn), tIn, tOut);
    };
    bool stop = false;
    if constexpr (kMethod == CcdMethod::Exact) {
      const Cubic g = cellCubic(c, wIn, wOut, sigma);
      cubicNonPositiveIntervals(g, [&](double a, double b) {
        if constexpr (kMode == CcdMode::FirstHit) {
          out.found = true;
          out.first = toT(a);
          stop = true;
          return false;
        } else {
          if (!out.found) {
            out.found = true;
            out.first = toT(a);
          }
          appendMerged(intervals, toT(a), toT(b));
          return true;
        }
      });
    } else {
      // Eq. (2): one crossing per cell assumed; a cell whose ends are on the same side is skipped (or, when
      // both ends are in contact, taken as entirely in contact). This is what misses the cases of Fig. 2.
      const double gIn = trilinear(c, wIn) - sigma;
      const double gOut = trilinear(c, wOut) - sigma;
      double a = 0.0, b = 0.0;
      bool any = true;
      if (gIn > 0.0 && gOut > 0.0) {
        any = false;
      } else if (gIn <= 0.0 && gOut <= 0.0) {
        a = tIn;
        b = tOut;
      } else {
        double lo = 0.0, hi = 1.0, gLo = gIn, gHi = gOut, beta = 0.0;
        const double residual = tolerance::kRegulaFalsiResidual * (std::abs(gIn) + std::abs(gOut));
        for (int iteration = 0; iteration < kBisectionIterations; ++iteration) {
          beta = lo + (hi - lo) * gLo / (gLo - gHi);
          const double gBeta = trilinear(c, wIn + beta * (wOut - wIn)) - sigma;
          if (std::abs(gBeta) <= residual) break;
          if ((gBeta <= 0.0) == (gLo <= 0.0)) {
            lo = beta;
            gLo = gBeta;
          } else {
            hi = beta;
            gHi = gBeta;
          }
        }
        if (gIn <= 0.0) {
          a = tIn;
          b = toT(beta);
        } else {
          a = toT(beta);
          b = tOut;
        }
      }
      if (any) {
        if (!out.found) {
          out.found = true;
          out.first = a;
        }
        if constexpr (kMode == CcdMode::FirstHit) {
          stop = true;
        } else {
          appendMerged(intervals, a, b);
        }
      }
    }
    if (stop || pointOnly) break;
    if (!walk.next()) break;
  }
}

}  // namespace sdfccd::detail
