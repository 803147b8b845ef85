/// @file
/// @brief `sdfccd bench bullet [--quick]`: the Bullet plugin against the paper's Section 5 figures.
///
/// @details Two protocols on the shipped scenes (assets/scenes/):
/// 1. Table 4: CCD time between the objects during a drop (drop-bunny: 777 points, 2,600 frames; drop-bowl:
///    2,072 points, 2,000 frames; drop-dragon: 437,645 points, 1,160 frames), point tree vs point by point
///    ("linear") on the *same* motion: the tree drives the simulation and, every n-th step, each query is
///    repeated point by point and timed (SdfccdContactSettings::shadowLinearEvery; n = 1 for bunny and bowl,
///    so their linear totals are measured, not estimated; the dragon's is extrapolated from every n-th step).
///    Bodies never sleep here, so every frame costs its CCD. Thread CPU time, one thread. Paper (2015 Xeon,
///    1024^3 fields): linear / tree = 8 / 2.5 s, 20.3 / 4.5 s, 671.6 / 2.6 s.
/// 2. Fig. 10a stability: 20 bunnies (drop-bunnies without friction and without time-of-impact clamping, so
///    only the penalty models differ). Under the scene's stiffness, the largest stable timestep of the
///    continuous and of the discrete model (paper: 3x larger for continuous); then at the continuous model's
///    largest stable timestep the discrete stiffness is lowered (x0.7 per try) until stable, and the two max
///    penetrations are compared (paper: discrete 2.75x deeper). "Stable": kStabilityCriterion
///    (bullet_stability_search.h, shared with the report's `stability` section).
#if __has_include("sdfccd/bullet/scene_world.h")  // built only with the Bullet plugin
#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bullet_stability_search.h"
#include "cli/bench_registry.h"
#include "sdfccd/atomic_file.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/error.h"

namespace sdfccd::cli {
namespace {

struct BenchBulletOptions {
  bool quick = false;
  std::string csv = "bench_bullet.csv";
  std::string scenes = "assets/scenes";
  std::string cache = "out/cache";
  std::string part = "all";
  std::string forceTiming = "same_step";
};

struct Table4Row {
  const char* label;
  const char* scene;
  double paperLinear;
  double paperTree;
  int shadowEvery;       // full run
  int shadowEveryQuick;  // --quick
};

std::ostringstream g_csv;

void csvRow(const std::string& part, const std::string& item, const std::string& key, double value) {
  g_csv << part << "," << item << "," << key << "," << value << "\n";
}

void runTable4(const BenchBulletOptions& o) {
  const Table4Row rows[] = {
      {"bunny", "drop-bunny.json", 8.0, 2.5, 1, 1},
      {"china bowl", "drop-bowl.json", 20.3, 4.5, 1, 1},
      {"dragon", "drop-dragon.json", 671.6, 2.6, 20, 100},
  };
  std::printf("\nTable 4: CCD time between the objects during a drop (s, one thread)%s\n",
              o.quick ? " -- QUICK: a quarter of the frames" : "");
  std::printf("%-11s %9s %7s | %11s %9s %8s | %11s %9s %8s | %9s\n", "model", "#points", "#frames", "linear", "tree",
              "speedup", "paper lin.", "paper tree", "speedup", "ground");
  for (const Table4Row& row : rows) {
    Scene scene = loadScene(o.scenes + "/" + row.scene);
    const int frames = o.quick ? scene.frames / 4 : scene.frames;
    SceneWorldSettings settings;
    settings.cacheDir = o.cache;
    settings.allowSleeping = false;
    settings.shadowLinearEvery = o.quick ? row.shadowEveryQuick : row.shadowEvery;
    SceneWorld world(scene, settings);
    for (int f = 0; f < frames; ++f) world.step();
    const SdfccdContactStatistics& stats = world.contacts().statistics();
    const double tree = stats.ccdSeconds - stats.groundCcdSeconds;
    const double linear =
        stats.shadowSteps > 0 ? stats.shadowLinearSeconds * double(frames) / double(stats.shadowSteps) : 0.0;
    const bool extrapolated = settings.shadowLinearEvery > 1;
    int points = 0;
    for (int i = 0; i < world.bodyCount(); ++i) points = std::max(points, int(world.model(i).shell().size()));
    std::printf("%-11s %9d %7d | %10.2f%s %9.2f %7.1fx | %11.1f %9.1f %7.1fx | %9.2f\n", row.label, points, frames,
                linear, extrapolated ? "*" : " ", tree, tree > 0 ? linear / tree : 0.0, row.paperLinear, row.paperTree,
                row.paperLinear / row.paperTree, stats.groundCcdSeconds);
    csvRow("table4", row.label, "points", points);
    csvRow("table4", row.label, "frames", frames);
    csvRow("table4", row.label, "linear_seconds", linear);
    csvRow("table4", row.label, "tree_seconds", tree);
    csvRow("table4", row.label, "ground_seconds", stats.groundCcdSeconds);
    csvRow("table4", row.label, "max_penetration_cells", world.maxPenetrationCells());
    csvRow("table4", row.label, "paper_linear_seconds", row.paperLinear);
    csvRow("table4", row.label, "paper_tree_seconds", row.paperTree);
  }
  std::printf("* extrapolated from every %d-th step (%d with --quick). Fields: 128^3 (paper: 1024^3).\n",
              rows[2].shadowEvery, rows[2].shadowEveryQuick);
}

// Prints the trials; CSV items are "<name>@<timestep>" (or "<name>@k<stiffness>" for a stiffness walk).
void printTrials(const char* name, const StabilitySearch& search, bool byStiffness = false) {
  for (const StabilityTrial& t : search.trials) {
    std::printf("  %-10s dt %.4f s, k %8.1f: %-8s max penetration %7.2f cells %s\n", name, t.timestep, t.stiffness,
                t.stable ? "stable" : "UNSTABLE", t.maxPenetrationCells, t.why.c_str());
    const std::string item = std::string(name) + (byStiffness ? "_softened@k" + std::to_string(t.stiffness)
                                                               : "@" + std::to_string(t.timestep));
    csvRow("fig10a", item, "stable", t.stable ? 1 : 0);
    csvRow("fig10a", item, "max_penetration_cells", t.maxPenetrationCells);
  }
}

void runFig10a(const BenchBulletOptions& o) {
  Scene base = loadScene(o.scenes + "/drop-bunnies.json");
  base.effects.erase("friction");
  StabilityTrialSettings trial;
  trial.stiffness = base.contact.stiffness;
  trial.duration = o.quick ? 0.8 : 1.5;
  trial.cacheDir = o.cache;
  trial.forceTiming = o.forceTiming == "same_step" ? SdfccdForceTiming::SameStep : SdfccdForceTiming::NextStep;
  const std::vector<double> timesteps =
      o.quick ? std::vector<double>{0.001, 0.002, 0.003, 0.004}
              : std::vector<double>{0.0005, 0.001, 0.0015, 0.002, 0.0025, 0.003, 0.004, 0.005, 0.006};
  std::printf(
      "\nFig. 10a: 20 bunnies, stiffness %.0f N/m per point, %.1f s simulated, force timing %s, no TOI "
      "clamping, no friction\n%s\n",
      trial.stiffness, trial.duration, o.forceTiming.c_str(), kStabilityCriterion);
  StabilitySearch searches[2];
  const PenaltyModel models[2] = {PenaltyModel::Continuous, PenaltyModel::Discrete};
  const char* names[2] = {"continuous", "discrete"};
  for (int m = 0; m < 2; ++m) {
    trial.model = models[m];
    searches[m] = largestStableTimestep(base, trial, timesteps);
    printTrials(names[m], searches[m]);
  }
  const double largest[2] = {searches[0].largest, searches[1].largest};
  std::printf("largest stable timestep: continuous %.4f s, discrete %.4f s: ratio %.2fx (paper: 3x)\n", largest[0],
              largest[1], largest[1] > 0 ? largest[0] / largest[1] : 0.0);
  csvRow("fig10a", "largest_stable_dt", "continuous", largest[0]);
  csvRow("fig10a", "largest_stable_dt", "discrete", largest[1]);
  if (largest[0] <= 0.0) return;
  // At the continuous model's largest stable timestep, soften the discrete model until it is stable.
  trial.model = PenaltyModel::Discrete;
  trial.timestep = largest[0];
  const StabilitySearch softened = softenUntilStable(base, trial, 0.7, 12);
  printTrials("discrete", softened, true);
  if (softened.largest <= 0.0) {
    std::printf("the discrete model found no stable stiffness at dt %.4f s\n", largest[0]);
    return;
  }
  const double continuousPenetration = searches[0].penetrationAtLargest;
  std::printf(
      "at dt %.4f s: discrete (k %.0f) max penetration %.2f cells vs continuous (k %.0f) %.2f cells: "
      "%.2fx deeper (paper: 2.75x)\n",
      largest[0], softened.largest, softened.penetrationAtLargest, trial.stiffness, continuousPenetration,
      continuousPenetration > 0 ? softened.penetrationAtLargest / continuousPenetration : 0.0);
  csvRow("fig10a", "softened_discrete", "stiffness", softened.largest);
  csvRow("fig10a", "softened_discrete", "max_penetration_cells", softened.penetrationAtLargest);
  csvRow("fig10a", "continuous_at_largest_dt", "max_penetration_cells", continuousPenetration);
}

int runBenchBullet(const BenchBulletOptions& o) {
  if (o.part != "all" && o.part != "table4" && o.part != "fig10a") throw Error("--part must be all, table4 or fig10a");
  if (o.forceTiming != "next_step" && o.forceTiming != "same_step") {
    throw Error("--force-timing must be next_step or same_step");
  }
  std::printf("sdfccd bench bullet%s -- %s\n", o.quick ? " --quick" : "", machineDescription().c_str());
  g_csv.str("");
  g_csv << "part,item,key,value\n";
  if (o.part != "fig10a") runTable4(o);
  if (o.part != "table4") runFig10a(o);
  if (!o.csv.empty()) {
    writeFileAtomically(o.csv, g_csv.str());
    std::printf("wrote %s\n", o.csv.c_str());
  }
  return 0;
}

const BenchRegistrar registrar("bullet", "Table 4 (CCD linear vs tree in drops) and Fig. 10a (stability)",
                               [](CLI::App& sub) {
                                 auto o = std::make_shared<BenchBulletOptions>();
                                 sub.add_flag("--quick", o->quick, "A quarter of the frames, fewer timesteps");
                                 sub.add_option("--out", o->csv, "CSV output (default bench_bullet.csv; empty: none)");
                                 sub.add_option("--scenes", o->scenes, "Scene folder (default assets/scenes)");
                                 sub.add_option("--cache", o->cache, "Body model cache (default out/cache)");
                                 sub.add_option("--part", o->part, "all, table4 or fig10a");
                                 sub.add_option("--force-timing", o->forceTiming,
                                                "Fig. 10a force timing: same_step (default) or next_step (the paper)");
                                 return std::function<int()>([o]() { return runBenchBullet(*o); });
                               });

}  // namespace
}  // namespace sdfccd::cli

#endif
