/// @file
/// @brief `sdfccd query FIELD --segments FILE [--sigma S] [--method exact|bisection] [--octree full|leaves|off]`:
/// continuous collision of segments with a field's level set (paper Sections 3.1, 3.2).
///
/// @details FILE holds one segment per line, `x0,y0,z0,x1,y1,z1`, with an optional 7th value overriding
/// sigma; blank lines and lines starting with `#` are skipped. Output on stdout, CSV: `segment,first_hit,
/// intervals`, one row per segment in input order: the 0-based index, the smallest t in [0,1] with
/// phi <= sigma (empty when none, 0 when the segment starts inside), and the merged `a:b` ranges separated by
/// spaces; t printed with 17 significant digits. The whole file is validated before anything is printed, so a
/// malformed line gives one error naming the line and no partial output.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/command_registry.h"
#include "cli/csv_numbers.h"
#include "cli/query_options.h"
#include "sdfccd/ccd/segment_file.h"
#include "sdfccd/error.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/field/sdf_file.h"

namespace sdfccd::cli {
namespace {

struct QueryOptions {
  std::string field;
  std::string segments;
  double sigma = 0.0;
  std::string method = "exact";
  std::string octree = "full";
};

int runQuery(const QueryOptions& o) {
  if (!std::isfinite(o.sigma)) throw Error("--sigma must be finite");
  SegmentCcdSettings settings;
  settings.method = parseCcdMethod(o.method);
  settings.octree = parseOctreeMode(o.octree);
  settings.mode = CcdMode::AllIntervals;
  const std::vector<SegmentRecord> segments = readSegmentFile(o.segments, o.sigma);
  const GridField field(std::make_shared<const SdfGrid>(loadSdf(o.field)));

  std::string out = "segment,first_hit,intervals\n";
  SegmentCcdResult result;
  for (std::size_t n = 0; n < segments.size(); ++n) {
    settings.sigma = segments[n].sigma;
    field.intersectSegment(segments[n].p0, segments[n].p1, settings, result);
    if (result.state == SegmentState::Failed) throw Error("segment " + std::to_string(n) + ": query failed");
    out += std::to_string(n);
    out += ',';
    if (result.hit()) appendCsvNumber(out, result.fraction);
    out += ',';
    appendCsvIntervals(out, result.intervals);
    out += '\n';
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  std::fflush(stdout);
  return 0;
}

const CommandRegistrar cmd_queryRegistrar("query", [](CLI::App& app) {
  auto o = std::make_shared<QueryOptions>();
  CLI::App* cmd = app.add_subcommand("query", "Continuous collision of segments with a field's level set (CSV out)");
  cmd->add_option("field", o->field, "Field file (native or SDFGen text)")->required();
  cmd->add_option("--segments", o->segments, "Segments file: x0,y0,z0,x1,y1,z1[,sigma] per line")->required();
  cmd->add_option("--sigma", o->sigma, "Level set value (default 0)");
  cmd->add_option("--method", o->method, "Root finding per cell: exact (default) or bisection");
  cmd->add_option("--octree", o->octree, "Cell skipping: full (default), leaves or off");
  return std::function<int()>([o]() { return runQuery(*o); });
});

}  // namespace
}  // namespace sdfccd::cli
