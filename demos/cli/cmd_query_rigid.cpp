/// @file
/// @brief `sdfccd query-rigid FIELD SHELL --motions FILE [--query earliest|all] [--sigma S]
/// [--method exact|bisection] [--octree full|leaves|off] [--tree on|off]`: continuous collision of a point shell
/// moving rigidly against a field's level set (paper Section 3.3), the rigid counterpart of `sdfccd query`.
///
/// @details SHELL is a shell file as `sdfccd sample` writes it (PLY or CSV, by extension). FILE holds one motion
/// per line, 14 comma-separated numbers: the shell's start pose, then its end pose, in the field's frame, each
/// a position x,y,z and a unit quaternion w,x,y,z (sdfFromShellStart, sdfFromShellEnd); blank lines and lines
/// starting with `#` are skipped. A quaternion must have unit norm within kUnitQuaternionTolerance and is
/// normalized before use. Each shell point moves on the straight segment between its start and end positions
/// (paper Section 3, as rigid_ccd.h does), so every point's answer is `sdfccd query`'s for that segment.
///
/// Output on stdout, CSV, fractions of the step with 17 significant digits, motions 0-based in input order:
/// - `--query earliest` (default): `motion,first_hit,points`, one row per motion: the earliest contact of any
///   point (empty when none, 0 when the shell starts in contact) and the space-separated indices of every
///   point whose first contact is exactly that fraction (rigidCcd's earliestOnly, ties kept).
/// - `--query all`: `motion,point,first_hit,intervals`, one row per point in contact, sorted by motion then
///   point: the point's first contact and its merged `a:b` ranges, as `sdfccd query` writes them.
/// `--tree off` queries point by point (the linear reference); the answers are identical. The whole motions
/// file is validated before anything is printed: a malformed line gives one error naming it, no output.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/command_registry.h"
#include "cli/csv_numbers.h"
#include "cli/query_options.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/error.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/field/sdf_file.h"
#include "sdfccd/shell/point_shell.h"
#include "sdfccd/shell/point_tree.h"

namespace sdfccd::cli {
namespace {

/// How far a motion's quaternion norm may be from 1. Loose enough for quaternions written with 7 digits,
/// tight enough that a typo (or a missing component) is caught rather than silently normalized away.
constexpr double kUnitQuaternionTolerance = 1e-6;

/// Numbers per motion line: start pose, end pose, each x,y,z,qw,qx,qy,qz.
constexpr std::size_t kMotionValues = 14;

struct QueryRigidOptions {
  std::string field;
  std::string shell;
  std::string motions;
  std::string query = "earliest";
  double sigma = 0.0;
  std::string method = "exact";
  std::string octree = "full";
  std::string tree = "on";
};

/// One line of the motions file.
struct ShellMotion {
  Rigid sdfFromShellStart;
  Rigid sdfFromShellEnd;
};

/// The pose of values[0..6] (x,y,z,qw,qx,qy,qz); `which` ("start"/"end") names it in errors.
Rigid poseFromValues(const double* values, const std::string& where, const char* which) {
  const Quat rotation(values[3], values[4], values[5], values[6]);  // Eigen's order: w, x, y, z
  const double norm = rotation.norm();
  if (!(std::abs(norm - 1.0) <= kUnitQuaternionTolerance)) {
    char buffer[160];
    std::snprintf(buffer, sizeof(buffer), "%s quaternion (w,x,y,z) has norm %.9g, not 1 (tolerance %g)", which, norm,
                  kUnitQuaternionTolerance);
    throw Error(where + buffer);
  }
  Rigid pose = Rigid::Identity();
  pose.linear() = rotation.normalized().toRotationMatrix();
  pose.translation() = Vec3(values[0], values[1], values[2]);
  return pose;
}

std::vector<ShellMotion> readMotions(const std::string& path) {
  std::vector<ShellMotion> motions;
  for (const CsvNumberLine& line : readCsvNumberLines(path, "motions")) {
    if (line.values.size() != kMotionValues) {
      throw Error(line.where +
                  "expected 14 comma-separated numbers (start x,y,z,qw,qx,qy,qz then end x,y,z,qw,qx,qy,qz), got " +
                  std::to_string(line.values.size()));
    }
    motions.push_back({poseFromValues(line.values.data(), line.where, "start"),
                       poseFromValues(line.values.data() + 7, line.where, "end")});
  }
  return motions;
}

RigidCcdSettings settingsFrom(const QueryRigidOptions& o) {
  if (!std::isfinite(o.sigma)) throw Error("--sigma must be finite");
  RigidCcdSettings settings;
  settings.sigma = o.sigma;
  if (o.query == "earliest") {
    // The time of impact with every point tied at it; a first hit per point is all the leaves need.
    settings.earliestOnly = true;
    settings.mode = CcdMode::FirstHit;
  } else if (o.query == "all") {
    settings.mode = CcdMode::AllIntervals;
  } else {
    throw Error("--query must be earliest or all, got '" + o.query + "'");
  }
  settings.method = parseCcdMethod(o.method);
  settings.octree = parseOctreeMode(o.octree);
  if (o.tree == "on") {
    settings.useTree = true;
  } else if (o.tree == "off") {
    settings.useTree = false;
  } else {
    throw Error("--tree must be on or off, got '" + o.tree + "'");
  }
  return settings;
}

int runQueryRigid(const QueryRigidOptions& o) {
  const RigidCcdSettings settings = settingsFrom(o);
  const std::vector<ShellMotion> motions = readMotions(o.motions);
  const PointTree tree(loadShell(o.shell));
  const GridField field(std::make_shared<const SdfGrid>(loadSdf(o.field)));

  std::string out = settings.earliestOnly ? "motion,first_hit,points\n" : "motion,point,first_hit,intervals\n";
  RigidCcdResult result;
  for (std::size_t m = 0; m < motions.size(); ++m) {
    rigidCcd(tree, field, motions[m].sdfFromShellStart, motions[m].sdfFromShellEnd, settings, result);
    const std::string motion = std::to_string(m);
    if (settings.earliestOnly) {
      out += motion;
      out += ',';
      // firstFraction is 1 both for no contact and for a contact at the very end: the contacts tell them apart.
      if (!result.contacts.empty()) appendCsvNumber(out, result.firstFraction);
      out += ',';
      for (std::size_t k = 0; k < result.contacts.size(); ++k) {
        if (k > 0) out += ' ';
        out += std::to_string(result.contacts[k].point);
      }
      out += '\n';
      continue;
    }
    for (const PointContact& contact : result.contacts) {
      out += motion;
      out += ',';
      out += std::to_string(contact.point);
      out += ',';
      appendCsvNumber(out, contact.fraction);
      out += ',';
      appendCsvIntervals(out, contact.intervals);
      out += '\n';
    }
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  std::fflush(stdout);
  return 0;
}

const CommandRegistrar cmd_query_rigidRegistrar("query-rigid", [](CLI::App& app) {
  auto o = std::make_shared<QueryRigidOptions>();
  CLI::App* cmd =
      app.add_subcommand("query-rigid", "Continuous collision of a rigidly moving point shell with a field (CSV out)");
  cmd->add_option("field", o->field, "Field file (native or SDFGen text)")->required();
  cmd->add_option("shell", o->shell, "Shell file as `sdfccd sample` writes it (.ply or .csv)")->required();
  cmd->add_option("--motions", o->motions,
                  "Motions file: start then end pose in the field's frame, x,y,z,qw,qx,qy,qz each, per line")
      ->required();
  cmd->add_option("--query", o->query, "earliest (default): time of impact and its points; all: every contact");
  cmd->add_option("--sigma", o->sigma, "Level set value (default 0)");
  cmd->add_option("--method", o->method, "Root finding per cell: exact (default) or bisection");
  cmd->add_option("--octree", o->octree, "Cell skipping: full (default), leaves or off");
  cmd->add_option("--tree", o->tree, "Point tree culling: on (default) or off (point by point, same answers)");
  return std::function<int()>([o]() { return runQueryRigid(*o); });
});

}  // namespace
}  // namespace sdfccd::cli
