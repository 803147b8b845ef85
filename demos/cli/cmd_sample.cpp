/// @file
/// @brief `sdfccd sample MESH --points N [--vertices] [--iterations K] [--seed S] -o SHELL`: a point shell of
/// a mesh (paper Section 3.3): N points spread by particle repulsion, or the mesh's vertices, written as PLY
/// or CSV (by the extension).
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "cli/command_registry.h"
#include "cli/progress_bar.h"
#include "sdfccd/error.h"
#include "sdfccd/io/mesh_loader.h"
#include "sdfccd/output_file.h"
#include "sdfccd/shell/point_shell.h"

namespace sdfccd::cli {
namespace {

struct SampleOptions {
  std::string mesh;
  std::string output;
  int points = 0;
  bool vertices = false;
  int iterations = 20;
  std::uint64_t seed = 12345;
  int threads = 0;
};

int runSample(const SampleOptions& o) {
  if (o.vertices == (o.points > 0)) throw Error("give either --points N (N >= 1) or --vertices");
  if (o.points < 0 || o.points > 100000000) throw Error("--points must be in 1..100000000");
  if (o.threads < 0 || o.threads > 1024) throw Error("--threads must be in 0..1024");
  checkOutput(o.output, {o.mesh});  // `-o MESH` and an unwritable output fail now, not after the sampling
  MeshRepairReport repairs;
  const TriangleMesh mesh = loadMesh(o.mesh, &repairs);
  const auto start = std::chrono::steady_clock::now();
  PointShell shell;
  if (o.vertices) {
    shell = shellFromVertices(mesh);
  } else {
    ShellSamplingSettings settings;
    settings.points = o.points;
    settings.iterations = o.iterations;
    settings.seed = o.seed;
    settings.threads = o.threads;
    ProgressBar bar("sampling");
    settings.progress = bar.callback();
    shell = sampleShell(mesh, settings);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  saveShell(shell, o.output);
  std::printf("mesh:    %s (%zu vertices, %zu triangles; %s)\n", o.mesh.c_str(), mesh.vertices.size(),
              mesh.triangles.size(), repairs.summary().c_str());
  if (o.vertices) {
    std::printf("shell:   %zu vertices with area-weighted normals\n", shell.size());
  } else {
    std::printf("shell:   %zu points, particle repulsion, %d iterations, seed %llu\n", shell.size(), o.iterations,
                static_cast<unsigned long long>(o.seed));
  }
  std::printf("time:    %.3f s\n", seconds);
  std::printf("output:  %s\n", o.output.c_str());
  return 0;
}

const CommandRegistrar cmd_sampleRegistrar("sample", [](CLI::App& app) {
  auto o = std::make_shared<SampleOptions>();
  CLI::App* cmd = app.add_subcommand("sample", "Make a point shell (points + outward normals) of a mesh");
  cmd->add_option("mesh", o->mesh, "Input mesh (OBJ, OFF, PLY, STL, ... through assimp)")->required();
  cmd->add_option("-o,--output", o->output, "Output shell: .ply (ascii) or .csv")->required();
  cmd->add_option("-n,--points", o->points, "Number of points spread over the surface by particle repulsion");
  cmd->add_flag("--vertices", o->vertices, "Use the mesh's vertices (area-weighted normals) instead");
  cmd->add_option("--iterations", o->iterations, "Repulsion iterations (default 20)");
  cmd->add_option("--seed", o->seed, "Seed of the initial random samples (default 12345)");
  cmd->add_option("-t,--threads", o->threads, "Worker threads (0 = all); the result does not depend on it");
  return std::function<int()>([o]() { return runSample(*o); });
});

}  // namespace
}  // namespace sdfccd::cli
