#include "cli/query_options.h"

#include "cli/csv_numbers.h"
#include "sdfccd/error.h"

namespace sdfccd::cli {

CcdMethod parseCcdMethod(const std::string& method) {
  if (method == "exact") return CcdMethod::Exact;
  if (method == "bisection") return CcdMethod::Bisection;
  throw Error("--method must be exact or bisection, got '" + method + "'");
}

OctreeMode parseOctreeMode(const std::string& octree) {
  if (octree == "full") return OctreeMode::Full;
  if (octree == "leaves") return OctreeMode::Leaves;
  if (octree == "off") return OctreeMode::Off;
  throw Error("--octree must be full, leaves or off, got '" + octree + "'");
}

void appendCsvIntervals(std::string& out, const IntervalList& intervals) {
  for (std::size_t k = 0; k < intervals.size(); ++k) {
    if (k > 0) out += ' ';
    appendCsvNumber(out, intervals[k].begin);
    out += ':';
    appendCsvNumber(out, intervals[k].end);
  }
}

}  // namespace sdfccd::cli
