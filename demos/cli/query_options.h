/// @file
/// @brief What `sdfccd query` and `sdfccd query-rigid` share: the `--method` and `--octree` strings turned into
/// their enums, and the `a:b` column of contact intervals.
///
/// @details Both commands accept the same spellings and give the same errors, and `query-rigid --query all`
/// writes a point's intervals exactly as `query` writes a segment's, so each lives here once.
#pragma once

#include <string>

#include "sdfccd/ccd/interval_list.h"
#include "sdfccd/ccd/segment_ccd.h"

namespace sdfccd::cli {

/// `--method`: "exact" or "bisection". Throws sdfccd::Error naming the option on anything else.
CcdMethod parseCcdMethod(const std::string& method);

/// `--octree`: "full", "leaves" or "off". Throws sdfccd::Error naming the option on anything else.
OctreeMode parseOctreeMode(const std::string& octree);

/// Appends the intervals as space-separated `a:b` ranges, each end with 17 significant digits (nothing when
/// there are none).
void appendCsvIntervals(std::string& out, const IntervalList& intervals);

}  // namespace sdfccd::cli
