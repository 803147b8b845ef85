/// @file
/// @brief The scaling benchmark (see bullet_scaling_bench.h).
#include "bench/bullet_scaling_bench.h"

#if __has_include("sdfccd/bullet/scene_world.h")  // built only with the Bullet plugin
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <thread>
#include <vector>

#include "bench/gimpact_peer.h"
#include "cli/line_plot.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/error.h"
#include "sdfccd/thread_cpu_time.h"

namespace sdfccd::cli {
namespace scaling_bench {  // named: the tool is a unity build

constexpr double kScalingPenaltyStep = 0.001;       // s: the paper's step
constexpr double kScalingSolverStep = 1.0 / 240.0;  // s: Bullet's usual fixed step
constexpr double kTargetPenalty = 0.5;              // target: 80 bunnies, real-time factor in penalty mode
constexpr double kTargetSolver = 1.0;               // and in solver mode
constexpr double kTargetSpeedup = 1.8;              // parallel speedup on 2 cores
constexpr int kTargetBodies = 80;

/// CPU time of the whole process, every thread (s).
double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

std::string loadAverage() {
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) != 3) return "unknown";
  char text[64];
  std::snprintf(text, sizeof text, "%.2f %.2f %.2f", load[0], load[1], load[2]);
  return text;
}

/// `count` bunnies in a pile-to-be: layers of n x n on a grid (n = ceil(sqrt(count / 4))), each layer shifted
/// against the one below, the shipped scene's orientations in turn; the scene's ground, gravity and effects.
Scene pileScene(const Scene& shipped, int count) {
  Scene scene = shipped;
  scene.bodies.clear();
  const int n = std::max(1, int(std::ceil(std::sqrt(count / 4.0))));
  for (int i = 0; i < count; ++i) {
    const int layer = i / (n * n);
    const int ix = (i % (n * n)) % n;
    const int iz = (i % (n * n)) / n;
    SceneBody body = shipped.bodies[std::size_t(i) % shipped.bodies.size()];
    body.name = "bunny" + std::to_string(i);
    body.position =
        Vec3((ix - 0.5 * (n - 1)) * 0.24 + 0.06 * (layer % 2), 0.2 + 0.25 * layer + 0.02 * ((ix + iz) % 3 - 1),
             (iz - 0.5 * (n - 1)) * 0.26 + 0.05 * (layer % 2));
    scene.bodies.push_back(body);
  }
  return scene;
}

struct ScalingRun {
  int frames = 0;
  double wall = 0.0;        // s, the steps
  double threadCpu = 0.0;   // s, the stepping thread
  double processCpu = 0.0;  // s, every thread of the process
  double queries = 0.0;     // CCD queries
  double batch = 0.0;       // s, wall time of the parallel batches (ContactStatistics::parallelWallSeconds)
};

/// Steps `step` for `seconds` of simulated time at `dt`; `queries` reads the CCD query counter.
ScalingRun timeSteps(const std::function<void()>& step, double dt, double seconds,
                     const std::function<double()>& queries) {
  ScalingRun run;
  run.frames = std::max(1, int(std::lround(seconds / dt)));
  const double q0 = queries();
  const double process0 = processCpuSeconds();
  const double thread0 = threadCpuSeconds();
  const auto wall0 = std::chrono::steady_clock::now();
  for (int f = 0; f < run.frames; ++f) step();
  run.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  run.threadCpu = threadCpuSeconds() - thread0;
  run.processCpu = processCpuSeconds() - process0;
  run.queries = queries() - q0;
  return run;
}

/// The run of median wall time (the lower one of the middle two for an even count).
ScalingRun medianRun(std::vector<ScalingRun> tries) {
  std::sort(tries.begin(), tries.end(), [](const ScalingRun& a, const ScalingRun& b) { return a.wall < b.wall; });
  return tries[(tries.size() - 1) / 2];
}

struct Config {
  const char* name;
  SdfccdContactMode mode;
  double dt;
  int threads;
};

}  // namespace scaling_bench

void runScalingBench(const ScalingBenchOptions& o, const ScalingCsvSink& csv) {
  using namespace scaling_bench;
  const Scene shipped = loadScene(o.scenes + "/drop-bunnies.json");
  std::vector<int> counts = o.quick ? std::vector<int>{4, 12} : std::vector<int>{20, 80, 320};
  if (!o.bodies.empty()) counts = o.bodies;
  for (int n : counts) {
    if (n < 1 || n > 5000)
      throw Error("--scaling-bodies: each pile size must be in 1..5000 (got " + std::to_string(n) + ")");
  }
  const double seconds = o.quick ? 0.1 : 1.5;
  if (o.repeat < 1 || o.repeat > 100) throw Error("--repeat: must be in 1..100 (got " + std::to_string(o.repeat) + ")");
  const Config configs[] = {{"penalty 1 ms, 1 thread", SdfccdContactMode::Penalty, kScalingPenaltyStep, 1},
                            {"penalty 1 ms, 2 threads", SdfccdContactMode::Penalty, kScalingPenaltyStep, 2},
                            {"solver 1/240 s, 1 thread", SdfccdContactMode::Solver, kScalingSolverStep, 1},
                            {"solver 1/240 s, 2 threads", SdfccdContactMode::Solver, kScalingSolverStep, 2}};
  std::printf(
      "\nScaling: bunnies (777 points, 128^3 fields) dropped into a pile, %.2f s simulated; contact "
      "defaults of a new world; %u hardware threads; %s; load average before: %s\n"
      "  wall and thread CPU of the steps; process CPU counts every thread (the pool's too). Other engineers share "
      "this machine: times are under load unless the load average says otherwise.\n",
      seconds, std::thread::hardware_concurrency(),
      o.repeat > 1 ? ("each row the median of " + std::to_string(o.repeat) + " runs, taken in turns").c_str()
                   : "one run per row",
      loadAverage().c_str());
  std::printf("  %-28s %6s %7s %9s %9s %9s %11s %8s %8s %7s\n", "world", "bodies", "steps", "wall ms", "thread ms",
              "proc ms", "ms/body/st", "ccd/st", "x real", "batch%");
  std::fflush(stdout);
  LinePlot plot;
  plot.title = "Step time per body (wall) against bodies in the pile";
  plot.xLabel = "bunnies";
  plot.yLabel = "wall ms per step and body";
  plot.logX = true;
  plot.logY = true;
  plot.legend = "outside right top";
  plot.width = 1000;
  std::vector<PlotSeries> series(std::size(configs) + 1);
  // wall[config][count]: for the speedups and the targets.
  std::vector<std::vector<ScalingRun>> runs(std::size(configs) + 1, std::vector<ScalingRun>(counts.size()));
  for (std::size_t k = 0; k < counts.size(); ++k) {
    const Scene pile = pileScene(shipped, counts[k]);
    std::vector<std::shared_ptr<const BodyModel>> models;
    // Every world `repeat` times, in turns; each row is then the run of median wall time.
    std::vector<std::vector<ScalingRun>> tries(std::size(configs) + 1);
    for (int r = 0; r < o.repeat; ++r) {
      for (std::size_t c = 0; c < std::size(configs); ++c) {
        Scene scene = pile;
        scene.contact = SceneContact{};
        scene.contact.mode = configs[c].mode;
        scene.timestep = configs[c].dt;
        bullet::SceneWorldSettings settings;
        settings.cacheDir = o.cache;
        settings.narrowphaseThreads = configs[c].threads;
        bullet::SceneWorld world(scene, settings);
        if (models.empty()) {
          for (int i = 0; i < world.bodyCount(); ++i) models.push_back(world.modelPtr(i));
        }
        const bullet::ContactStatistics& stats = world.contacts().statistics();
        const double batch0 = stats.parallelWallSeconds;
        ScalingRun run = timeSteps([&world] { world.step(); }, configs[c].dt, seconds,
                                   [&stats] { return double(stats.ccdQueries); });
        run.batch = stats.parallelWallSeconds - batch0;
        tries[c].push_back(run);
      }
      GImpactPeer hulls(pile, models, PeerShape::ConvexHull, kScalingSolverStep);
      tries.back().push_back(timeSteps([&hulls] { hulls.step(); }, kScalingSolverStep, seconds, [] { return 0.0; }));
      if (o.repeat > 1) std::fprintf(stderr, "scaling: %d bunnies, round %d of %d done\n", counts[k], r + 1, o.repeat);
    }
    for (std::size_t c = 0; c < tries.size(); ++c) runs[c][k] = medianRun(tries[c]);
    csv("scaling", std::to_string(counts[k]) + " bunnies", "runs_per_row", o.repeat);
    for (std::size_t c = 0; c <= std::size(configs); ++c) {
      const ScalingRun& r = runs[c][k];
      const char* name = c < std::size(configs) ? configs[c].name : "convex hulls 1/240 s (Bullet)";
      const double dt = c < std::size(configs) ? configs[c].dt : kScalingSolverStep;
      const double perBody = 1e3 * r.wall / r.frames / counts[k];
      const double realTime = r.frames * dt / r.wall;
      std::printf("  %-28s %6d %7d %9.1f %9.1f %9.1f %11.4f %8.1f %8.3f %6.1f%%\n", name, counts[k], r.frames,
                  1e3 * r.wall, 1e3 * r.threadCpu, 1e3 * r.processCpu, perBody, r.queries / r.frames, realTime,
                  r.wall > 0 ? 100.0 * r.batch / r.wall : 0.0);
      const std::string item = std::string(name) + " / " + std::to_string(counts[k]);
      csv("scaling", item, "wall_seconds", r.wall);
      csv("scaling", item, "thread_cpu_seconds", r.threadCpu);
      csv("scaling", item, "process_cpu_seconds", r.processCpu);
      csv("scaling", item, "wall_ms_per_step_and_body", perBody);
      csv("scaling", item, "ccd_queries_per_step", r.queries / r.frames);
      csv("scaling", item, "batch_share_of_wall", r.wall > 0 ? r.batch / r.wall : 0.0);
      csv("scaling", item, "real_time_factor", realTime);
      series[c].label = name;
      series[c].x.push_back(counts[k]);
      series[c].y.push_back(perBody);
    }
    std::fflush(stdout);
  }
  std::printf("  parallel speedup (wall, 1 thread / 2 threads):");
  for (std::size_t k = 0; k < counts.size(); ++k) {
    const double penalty = runs[0][k].wall / runs[1][k].wall;
    const double solver = runs[2][k].wall / runs[3][k].wall;
    std::printf("  %d bunnies: penalty %.2fx, solver %.2fx;", counts[k], penalty, solver);
    csv("scaling", "speedup / " + std::to_string(counts[k]), "penalty", penalty);
    csv("scaling", "speedup / " + std::to_string(counts[k]), "solver", solver);
  }
  // Under load the wall clock measures the other engineers' jobs as much as ours; the stepping thread's CPU time is
  // the critical path when a core is free for the worker (an upper bound: waiting for the worker costs no CPU).
  std::printf("\n  stepping thread CPU, 1 thread / 2 threads (what an idle machine approaches):");
  for (std::size_t k = 0; k < counts.size(); ++k) {
    const double penalty = runs[0][k].threadCpu / runs[1][k].threadCpu;
    const double solver = runs[2][k].threadCpu / runs[3][k].threadCpu;
    std::printf("  %d bunnies: penalty %.2fx, solver %.2fx;", counts[k], penalty, solver);
    csv("scaling", "cpu speedup / " + std::to_string(counts[k]), "penalty", penalty);
    csv("scaling", "cpu speedup / " + std::to_string(counts[k]), "solver", solver);
  }
  std::printf("\n  load average after: %s\n", loadAverage().c_str());
  const auto target = std::find(counts.begin(), counts.end(), kTargetBodies);
  if (target != counts.end()) {
    const std::size_t k = std::size_t(target - counts.begin());
    auto realTime = [&](std::size_t c) { return runs[c][k].frames * configs[c].dt / runs[c][k].wall; };
    std::printf("  scaling targets (idle machine) vs ours, %d bunnies, 2 threads:\n", kTargetBodies);
    std::printf("    penalty 1 ms real-time factor   >= %.2fx   ours %.3fx\n", kTargetPenalty, realTime(1));
    std::printf("    solver 1/240 s real-time factor >= %.2fx   ours %.3fx\n", kTargetSolver, realTime(3));
    std::printf("    parallel speedup on 2 cores     >= %.2fx   ours penalty %.2fx, solver %.2fx\n", kTargetSpeedup,
                runs[0][k].wall / runs[1][k].wall, runs[2][k].wall / runs[3][k].wall);
  }
  series.back().label = "convex hulls 1/240 s (Bullet)";
  plot.series = series;
  if (!o.plot.empty()) {
    try {
      writeLinePlot(plot, o.plot);
      std::printf("  wrote %s\n", o.plot.c_str());
    } catch (const Error& e) {
      std::printf("  no plot: %s\n", e.what());
    }
  }
}

}  // namespace sdfccd::cli

#endif
