/// @file
/// @brief `sdfccd bench sdf [--quick] [--out CSV]`: the paper's Table 1 (SDF build time and memory, bunny).
///
/// @details Builds the bunny's SDF at 128, 256 and 512 cells along the longest axis (padding 0, like the
/// paper's grid sizes) and prints our time and grid memory beside the paper's (8 threads of a 2015 Xeon).
/// The paper's bunny had 777 vertices; ours (assets/meshes/bunny.off) has 75,408 triangles.
#include <cstdio>
#include <ctime>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "bench/option_checks.h"
#include "cli/bench_registry.h"
#include "sdfccd/error.h"
#include "sdfccd/io/mesh_loader.h"
#include "sdfccd/mesh/sdf_builder.h"
#include "sdfccd/parallel_for.h"

#ifndef SDFCCD_ASSETS_DIR_CLI
#define SDFCCD_ASSETS_DIR_CLI "assets"
#endif

namespace sdfccd::cli {
namespace {

struct BenchSdfOptions {
  bool quick = false;
  std::string csv = "bench_sdf.csv";
  std::string mesh;
  int threads = 0;
  int padding = 0;
};

struct PaperRow {
  int resolution;
  double seconds;
  double megabytes;
};

// The 1-minute load average: a benchmark on a shared machine says how busy the machine was.
std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string first;
  in >> first;
  return first.empty() ? "?" : first;
}

int runBenchSdf(const BenchSdfOptions& o) {
  const std::string meshPath = o.mesh.empty() ? std::string(SDFCCD_ASSETS_DIR_CLI) + "/meshes/bunny.off" : o.mesh;
  std::vector<PaperRow> rows = {{128, 1.9, 8.2}, {256, 6.8, 64.8}, {512, 45.6, 518.0}};
  if (o.quick) rows = {{64, 0.0, 0.0}, {128, 1.9, 8.2}};
  MeshRepairReport repairs;
  const TriangleMesh mesh = loadMesh(meshPath, &repairs);
  const int threads = o.threads > 0 ? o.threads : defaultThreadCount();
  std::printf("Table 1: SDF build time and memory, %s (%zu triangles; the paper's bunny had 777 vertices)\n",
              meshPath.c_str(), mesh.triangles.size());
  std::printf("machine: %s; %d threads (paper: 8 threads of a 2015 Xeon)\n", machineDescription().c_str(), threads);
  std::printf("%-10s %-16s %10s %10s %9s %11s %12s %12s %7s %s\n", "resolution", "nodes", "ours [s]", "paper [s]",
              "CPU [s]", "ours [MB]", "paper [MB]", "extra [MB]", "load", "sign");
  std::ofstream csv;
  if (!o.csv.empty()) {
    csv.open(o.csv);
    if (!csv) throw Error("cannot write '" + o.csv + "'");
    csv << "resolution,nodes_x,nodes_y,nodes_z,threads,seconds,paper_seconds,cpu_seconds,grid_mb,paper_mb,extra_mb,"
           "load_average,sign,mean_candidates,machine\n";
  }
  for (const PaperRow& row : rows) {
    SdfBuildSettings settings;
    settings.resolution = row.resolution;
    settings.padding = o.padding;
    settings.threads = threads;
    const std::clock_t cpuStart = std::clock();
    const SdfBuildResult r = buildSdf(mesh, settings);
    const double cpuSeconds = static_cast<double>(std::clock() - cpuStart) / CLOCKS_PER_SEC;
    const std::string load = loadAverage();
    const Vec3i n = r.grid->nodeCounts();
    const double mb = r.stats.gridBytes / 1e6;
    const double extra = r.stats.peakExtraBytes / 1e6;
    char nodes[64];
    std::snprintf(nodes, sizeof(nodes), "%dx%dx%d", n.x(), n.y(), n.z());
    char paperSeconds[32] = "-", paperMb[32] = "-";
    if (row.seconds > 0.0) {
      std::snprintf(paperSeconds, sizeof(paperSeconds), "%.1f", row.seconds);
      std::snprintf(paperMb, sizeof(paperMb), "%.1f", row.megabytes);
    }
    std::printf("%-10d %-16s %10.2f %10s %9.2f %11.1f %12s %12.1f %7s %s\n", row.resolution, nodes, r.stats.seconds,
                paperSeconds, cpuSeconds, mb, paperMb, extra, load.c_str(), toString(r.stats.signMethod));
    std::fflush(stdout);
    if (csv) {
      csv << row.resolution << ',' << n.x() << ',' << n.y() << ',' << n.z() << ',' << threads << ',' << r.stats.seconds
          << ',' << row.seconds << ',' << cpuSeconds << ',' << mb << ',' << row.megabytes << ',' << extra << ',' << load
          << ',' << toString(r.stats.signMethod) << ',' << r.stats.meanCandidates << ",\"" << machineDescription()
          << "\"\n";
    }
  }
  std::printf("memory: grid values as float32 (MB = 1e6 bytes); the paper's figures are (N+1)^3 floats in MiB.\n");
  std::printf("CPU: process CPU time of the build (all threads); load: 1-minute load average after the build.\n");
  if (!o.csv.empty()) std::printf("wrote %s\n", o.csv.c_str());
  return 0;
}

const BenchRegistrar bench_sdfRegistrar("sdf", "Table 1: SDF build time and memory for the bunny", [](CLI::App& sub) {
  auto o = std::make_shared<BenchSdfOptions>();
  sub.add_flag("--quick", o->quick, "Only 64^3 and 128^3");
  sub.add_option("--out", o->csv, "CSV output (default bench_sdf.csv; empty: none)");
  sub.add_option("--mesh", o->mesh, "Mesh (default: assets/meshes/bunny.off)")->check(nonEmpty());
  sub.add_option("--threads", o->threads, "Worker threads (0 = all)")->check(countIn(0, 1024));
  sub.add_option("--padding", o->padding, "Padding cells (default 0)")->check(countIn(0, 1000));
  return std::function<int()>([o]() { return runBenchSdf(*o); });
});

}  // namespace
}  // namespace sdfccd::cli
