/// @file
/// @brief `sdfccd build-sdf MESH --resolution N [--padding P] [--threads T] [--format native|sdfgen] -o OUT`:
/// the exact signed distance field of a mesh (paper Section 5, Table 1).
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>

#include "cli/command_registry.h"
#include "cli/progress_bar.h"
#include "sdfccd/error.h"
#include "sdfccd/field/sdf_file.h"
#include "sdfccd/io/mesh_loader.h"
#include "sdfccd/mesh/sdf_builder.h"
#include "sdfccd/output_file.h"

namespace sdfccd::cli {
namespace {

struct BuildSdfOptions {
  std::string mesh;
  std::string output;
  std::string format;
  std::string sign = "automatic";
  int resolution = 128;
  int padding = 4;
  int threads = 0;
  double maxMemoryMiB = 0.0;  // 0: half the physical memory
};

SdfSignMethod parseSign(const std::string& name) {
  if (name == "automatic") return SdfSignMethod::Automatic;
  if (name == "pseudonormal") return SdfSignMethod::Pseudonormal;
  if (name == "winding-number") return SdfSignMethod::WindingNumber;
  throw Error("unknown sign method '" + name + "' (expected automatic, pseudonormal or winding-number)");
}

int runBuildSdf(const BuildSdfOptions& o) {
  if (o.threads < 0 || o.threads > 1024) throw Error("--threads must be in 0..1024, got " + std::to_string(o.threads));
  if (!(o.maxMemoryMiB >= 0.0)) throw Error("--max-memory must be positive");
  double maxMemoryMiB = o.maxMemoryMiB;
  if (maxMemoryMiB == 0.0) {
    // Half the machine's memory: the grid values plus the builder's temporaries must fit comfortably.
    const double physical =
        static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGESIZE));
    maxMemoryMiB = physical > 0.0 ? std::min(0.5 * physical / (1024.0 * 1024.0), 65536.0) : 4096.0;
  }
  const SdfFileFormat format = o.format.empty() ? sdfFileFormatForPath(o.output) : parseSdfFileFormat(o.format);
  SdfBuildSettings settings;
  settings.resolution = o.resolution;
  settings.padding = o.padding;
  settings.threads = o.threads;
  settings.signMethod = parseSign(o.sign);
  settings.maxMemoryBytes = static_cast<std::size_t>(maxMemoryMiB * 1024.0 * 1024.0);

  // `-o MESH` and an output that cannot be written fail now, not after the build.
  checkOutput(o.output, {o.mesh});
  MeshRepairReport repairs;
  const TriangleMesh mesh = loadMesh(o.mesh, &repairs);
  // Checks the parameters and the memory before any heavy work.
  const SdfGridLayout layout = computeSdfGridLayout(mesh.bounds(), settings);
  (void)layout;
  SdfBuildResult result;
  {
    ProgressBar bar("building SDF");
    settings.progress = bar.callback();
    result = buildSdf(mesh, settings);
  }
  saveSdf(o.output, *result.grid, format);

  FILE* report = o.output == "-" ? stderr : stdout;  // `-o -`: the field alone on stdout
  const SdfGrid& grid = *result.grid;
  const SdfBuildStats& s = result.stats;
  std::fprintf(report, "mesh:        %s (%zu vertices, %zu triangles)\n", o.mesh.c_str(), mesh.vertices.size(),
               mesh.triangles.size());
  std::fprintf(report, "repairs:     %s\n", repairs.summary().c_str());
  std::fprintf(report, "dimensions:  %d x %d x %d nodes (resolution %d, padding %d)\n", grid.nodeCounts().x(),
               grid.nodeCounts().y(), grid.nodeCounts().z(), o.resolution, o.padding);
  std::fprintf(report, "spacing:     %.9g\n", grid.spacing());
  std::fprintf(report, "box:         [%.9g %.9g %.9g] - [%.9g %.9g %.9g]\n", grid.box().min().x(), grid.box().min().y(),
               grid.box().min().z(), grid.box().max().x(), grid.box().max().y(), grid.box().max().z());
  std::fprintf(report, "values:      %.9g .. %.9g\n", grid.minValue(), grid.maxValue());
  std::fprintf(report, "sign method: %s\n", toString(s.signMethod));
  std::fprintf(report, "build time:  %.3f s (distances %.3f s, sign %.3f s, %d threads)\n", s.seconds,
               s.distanceSeconds, s.signSeconds, s.threads);
  std::fprintf(report, "memory:      %.1f MiB grid values, %.1f MiB temporary\n", s.gridBytes / (1024.0 * 1024.0),
               s.peakExtraBytes / (1024.0 * 1024.0));
  std::fprintf(report, "output:      %s (%s)\n", o.output.c_str(), toString(format));
  return 0;
}

const CommandRegistrar cmd_build_sdfRegistrar("build-sdf", [](CLI::App& app) {
  auto o = std::make_shared<BuildSdfOptions>();
  CLI::App* cmd = app.add_subcommand("build-sdf", "Build the exact signed distance field of a mesh");
  cmd->add_option("mesh", o->mesh, "Input mesh (OBJ, OFF, PLY, STL, glTF, ... through assimp)")->required();
  cmd->add_option("-o,--output", o->output, "Output field (.sdfgen: SDFGen text; otherwise native; - for stdout)")
      ->required();
  cmd->add_option("-r,--resolution", o->resolution, "Cells along the longest side of the mesh's box (1..4096)")
      ->required();
  cmd->add_option("-p,--padding", o->padding, "Extra cells around the mesh's box (default 4)");
  cmd->add_option("-t,--threads", o->threads, "Worker threads (0 = all)");
  cmd->add_option("--format", o->format, "Output format: native or sdfgen (default: from the extension)");
  cmd->add_option("--sign", o->sign, "Sign method: automatic, pseudonormal or winding-number");
  cmd->add_option("--max-memory", o->maxMemoryMiB,
                  "Refuse grids over this many MiB (default: half the physical memory)");
  return std::function<int()>([o]() { return runBuildSdf(*o); });
});

}  // namespace
}  // namespace sdfccd::cli
