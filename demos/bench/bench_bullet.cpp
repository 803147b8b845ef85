/// @file
/// @brief `sdfccd bench bullet [--quick]`: the Bullet plugin against the paper's Section 5 figures.
///
/// @details Two protocols on the shipped scenes (assets/scenes/):
/// 1. Table 4: CCD time between the objects during a drop (drop-bunny: 777 points, 2,600 frames; drop-bowl:
///    2,072 points, 2,000 frames; drop-dragon: 437,645 points, 1,160 frames), point tree vs point by point
///    ("linear") on the *same* motion: the tree drives the simulation and, every n-th step, each query is
///    repeated point by point and timed (SceneWorldSettings::shadowLinearEvery; n = 1 for bunny and bowl,
///    so their linear totals are measured, not estimated; the dragon's is extrapolated from every n-th step).
///    Bodies never sleep here, so every frame costs its CCD. Thread CPU time, one thread. Paper (2015 Xeon,
///    1024^3 fields): linear / tree = 8 / 2.5 s, 20.3 / 4.5 s, 671.6 / 2.6 s. Each drop runs twice: the fresh
///    tree (with the linear repeats), then the coherent tree (ContactSettings::coherentCcd: each pair and
///    role starts from its last front, rigid_ccd_coherence.h; same contacts, so the same motion). Then the
///    20-bunny drop (drop-bunnies as shipped): its whole CCD time, fresh vs coherent.
/// 2. Fig. 10a stability: 20 bunnies (drop-bunnies without friction and without time-of-impact clamping, so
///    only the penalty models differ). Under the scene's stiffness, the largest stable timestep of the
///    continuous and of the discrete model (paper: 3x larger for continuous); then at the continuous model's
///    largest stable timestep the discrete stiffness is lowered (x0.7 per try) until stable, and the two max
///    penetrations are compared (paper: discrete 2.75x deeper). "Stable": kStabilityCriterion
///    (bullet_stability_search.h, shared with the report's `stability` section).
/// 3. The peer in the same run (not in the paper): the 20-bunny drop (drop-bunnies, as shipped) in our world
///    and in a plain Bullet world with btGImpactMeshShape (gimpact_peer.h: same bodies, masses, poses,
///    timestep and ground; Bullet's defaults otherwise), stepped in turns: step time (thread CPU and wall),
///    max penetration (penetration_probe.h: mesh vertices below the ground and inside the other body's
///    field, measured the same way for both, every --peer-every frames) and tunnelled bodies. GImpact takes
///    seconds per step once the bunnies touch, so only the first --peer-frames (400: both layers land) run.
/// 4. Modes and stable steps (bullet_mode_bench.h); scaling: piles of 20-320 bunnies on 1 and 2 narrowphase
///    threads beside Bullet's convex hulls (bullet_scaling_bench.h).
#if __has_include("sdfccd/bullet/scene_world.h")  // built only with the Bullet plugin
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bullet_mode_bench.h"
#include "bench/bullet_scaling_bench.h"
#include "bench/bullet_stability_search.h"
#include "bench/cache_option.h"
#include "bench/gimpact_peer.h"
#include "bench/option_checks.h"
#include "bench/penetration_probe.h"
#include "cli/bench_registry.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/error.h"
#include "sdfccd/output_file.h"
#include "sdfccd/thread_cpu_time.h"

namespace sdfccd::cli {
namespace {

struct BenchBulletOptions {
  bool quick = false;
  std::string csv = "bench_bullet.csv";
  std::string scenes = "assets/scenes";
  std::string cache;  // resolved by resolveCacheOption before the run
  std::string part = "all";
  std::string forceTiming = "same_step";
  int peerEvery = 1;                              // penetration measured every n-th frame in the peer comparison
  int peerFrames = 400;                           // frames of the peer comparison (0: the scene's); --quick halves it
  ModeBenchOptions modes;                         // --part modes and stable
  std::string scalingPlot = "bench_scaling.png";  // --part scaling's PNG
  std::vector<int> scalingBodies;                 // --part scaling's pile sizes (empty: the defaults)
  int repeat = 1;  // --part table4 and scaling: runs of each measurement, the median reported
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

/// The median (the lower one of the middle two for an even count) of a measurement's repeats (--repeat).
double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[(values.size() - 1) / 2];
}

/// Computes each body's field culling bounds (field_culling_bounds.h) before the clock starts: a field computes them at
/// its first tree query, once (tens of milliseconds for a 128^3 field), which the timed drop would otherwise count as
/// CCD time of its first step (a setup, like the field's build: the paper's Table 1, not Table 4).
void warmFields(const bullet::SceneWorld& world) {
  for (int i = 0; i < world.bodyCount(); ++i) (void)world.model(i).field().cullingBounds();
}

// One drop of a Table 4 scene; the CCD times between the objects (s, thread CPU).
struct Table4Run {
  double tree = 0.0;    // the tree's queries (fresh or coherent)
  double linear = 0.0;  // the point-by-point repeats, over every frame (extrapolated when shadowEvery > 1)
  double ground = 0.0;
  int points = 0;
  double maxPenetrationCells = 0.0;
};

Table4Run runTable4Scene(const Scene& scene, int frames, const BenchBulletOptions& o, int shadowEvery, bool coherent) {
  bullet::SceneWorldSettings settings;
  settings.cacheDir = o.cache;
  settings.allowSleeping = false;
  settings.shadowLinearEvery = shadowEvery;
  settings.coherentCcd = coherent;
  bullet::SceneWorld world(scene, settings);
  warmFields(world);
  for (int f = 0; f < frames; ++f) world.step();
  const bullet::ContactStatistics& stats = world.contacts().statistics();
  Table4Run run;
  run.tree = stats.ccdSeconds - stats.groundCcdSeconds;
  run.linear = stats.shadowSteps > 0 ? stats.shadowLinearSeconds * double(frames) / double(stats.shadowSteps) : 0.0;
  run.ground = stats.groundCcdSeconds;
  for (int i = 0; i < world.bodyCount(); ++i) run.points = std::max(run.points, int(world.model(i).shell().size()));
  run.maxPenetrationCells = world.maxPenetrationCells();
  return run;
}

// The 20-bunny drop as shipped (sleeping allowed), fresh vs coherent: every CCD query of the step (ground too).
void runPileCcd(const BenchBulletOptions& o) {
  const Scene scene = loadScene(o.scenes + "/drop-bunnies.json");
  const int frames = o.quick ? scene.frames / 4 : scene.frames;
  std::vector<double> tries[2];
  for (int r = 0; r < o.repeat; ++r) {
    for (int coherent = 0; coherent < 2; ++coherent) {
      bullet::SceneWorldSettings settings;
      settings.cacheDir = o.cache;
      settings.coherentCcd = coherent == 1;
      bullet::SceneWorld world(scene, settings);
      warmFields(world);
      for (int f = 0; f < frames; ++f) world.step();
      tries[coherent].push_back(world.contacts().statistics().ccdSeconds);
    }
  }
  const double seconds[2] = {median(tries[0]), median(tries[1])};
  std::printf("20-bunny drop (drop-bunnies, %d frames): CCD %.3f s fresh, %.3f s coherent (%.2fx)\n", frames,
              seconds[0], seconds[1], seconds[1] > 0 ? seconds[0] / seconds[1] : 0.0);
  csvRow("table4", "20 bunnies", "ccd_seconds", seconds[0]);
  csvRow("table4", "20 bunnies", "coherent_ccd_seconds", seconds[1]);
}

// Each scene twice on the same motion (the coherent query's contacts are the fresh one's bit for bit): the fresh
// tree with the point-by-point repeats, then the tree started from each pair's last front (coherent).
void runTable4(const BenchBulletOptions& o) {
  const Table4Row rows[] = {
      {"bunny", "drop-bunny.json", 8.0, 2.5, 1, 1},
      {"china bowl", "drop-bowl.json", 20.3, 4.5, 1, 1},
      {"dragon", "drop-dragon.json", 671.6, 2.6, 20, 100},
  };
  std::printf("\nTable 4: CCD time between the objects during a drop (s, one thread)%s%s\n",
              o.quick ? " -- QUICK: a quarter of the frames" : "",
              o.repeat > 1 ? (", each time the median of " + std::to_string(o.repeat) + " drops").c_str() : "");
  std::printf("%-11s %9s %7s | %11s %9s %8s | %9s %8s | %11s %9s %8s | %9s\n", "model", "#points", "#frames", "linear",
              "tree", "speedup", "coherent", "speedup", "paper lin.", "paper tree", "speedup", "ground");
  for (const Table4Row& row : rows) {
    Scene scene = loadScene(o.scenes + "/" + row.scene);
    const int frames = o.quick ? scene.frames / 4 : scene.frames;
    const int shadowEvery = o.quick ? row.shadowEveryQuick : row.shadowEvery;
    // With --repeat: fresh and coherent drops in turns, each column the median of its repeats.
    Table4Run fresh;
    Table4Run coherent;
    std::vector<double> linears, trees, coherentTrees, grounds;
    for (int r = 0; r < o.repeat; ++r) {
      fresh = runTable4Scene(scene, frames, o, shadowEvery, false);
      coherent = runTable4Scene(scene, frames, o, 0, true);
      linears.push_back(fresh.linear);
      trees.push_back(fresh.tree);
      grounds.push_back(fresh.ground);
      coherentTrees.push_back(coherent.tree);
    }
    fresh.linear = median(linears);
    fresh.tree = median(trees);
    fresh.ground = median(grounds);
    coherent.tree = median(coherentTrees);
    const double linear = fresh.linear;
    const bool extrapolated = shadowEvery > 1;
    std::printf("%-11s %9d %7d | %10.2f%s %9.2f %7.1fx | %9.2f %7.1fx | %11.1f %9.1f %7.1fx | %9.2f\n", row.label,
                fresh.points, frames, linear, extrapolated ? "*" : " ", fresh.tree,
                fresh.tree > 0 ? linear / fresh.tree : 0.0, coherent.tree,
                coherent.tree > 0 ? linear / coherent.tree : 0.0, row.paperLinear, row.paperTree,
                row.paperLinear / row.paperTree, fresh.ground);
    csvRow("table4", row.label, "points", fresh.points);
    csvRow("table4", row.label, "frames", frames);
    csvRow("table4", row.label, "linear_seconds", linear);
    csvRow("table4", row.label, "tree_seconds", fresh.tree);
    csvRow("table4", row.label, "coherent_tree_seconds", coherent.tree);
    csvRow("table4", row.label, "ground_seconds", fresh.ground);
    csvRow("table4", row.label, "max_penetration_cells", fresh.maxPenetrationCells);
    csvRow("table4", row.label, "coherent_max_penetration_cells", coherent.maxPenetrationCells);
    csvRow("table4", row.label, "paper_linear_seconds", row.paperLinear);
    csvRow("table4", row.label, "paper_tree_seconds", row.paperTree);
  }
  // The period this run used first (a quick run's footnote named the full run's).
  std::printf(
      "* extrapolated from every %d-th step (%d %s). Fields: 128^3 (paper: 1024^3).\n"
      "coherent: the tree started from each pair's last front (same contacts); speedups are over linear.\n",
      o.quick ? rows[2].shadowEveryQuick : rows[2].shadowEvery,
      o.quick ? rows[2].shadowEvery : rows[2].shadowEveryQuick, o.quick ? "in a full run" : "with --quick");
  runPileCcd(o);
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
  base.contact.direction = PenaltyDirection::ShellNormal;  // the paper's models (Fig. 10 compares those)
  StabilityTrialSettings trial;
  trial.stiffness = base.contact.stiffness;
  trial.duration = o.quick ? 0.8 : 1.5;
  trial.cacheDir = o.cache;
  trial.forceTiming = o.forceTiming == "same_step" ? ForceTiming::SameStep : ForceTiming::NextStep;
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

void runPeer(const BenchBulletOptions& o) {
  const Scene scene = loadScene(o.scenes + "/drop-bunnies.json");
  // GImpact needs seconds per step once the bunnies touch: by default the first 0.4 s (both layers land).
  const int wanted = o.peerFrames > 0 ? std::min(o.peerFrames, scene.frames) : scene.frames;
  const int frames = o.quick ? std::max(1, wanted / 2) : wanted;
  bullet::SceneWorldSettings settings;
  settings.cacheDir = o.cache;  // sleeping as the scene says, in both worlds
  bullet::SceneWorld ours(scene, settings);
  std::vector<std::shared_ptr<const BodyModel>> models;
  std::vector<bool> isStatic;
  for (int i = 0; i < ours.bodyCount(); ++i) {
    models.push_back(ours.modelPtr(i));
    isStatic.push_back(ours.isStatic(i));
  }
  GImpactPeer peer(scene, models);
  const PenetrationProbe probe(models, isStatic,
                               scene.has("ground") ? std::optional<double>(scene.groundHeight) : std::nullopt);
  auto oursPoses = [&]() {
    std::vector<Rigid> poses;
    for (int i = 0; i < ours.bodyCount(); ++i) {
      const bullet::SceneBodyState s = ours.bodyState(i);
      Rigid r = Rigid::Identity();
      r.linear() = s.orientation.normalized().toRotationMatrix();
      r.translation() = s.position;
      poses.push_back(r);
    }
    return poses;
  };
  auto peerPoses = [&]() {
    std::vector<Rigid> poses;
    for (int i = 0; i < peer.bodyCount(); ++i) poses.push_back(peer.worldFromBody(i));
    return poses;
  };
  std::printf(
      "\nThe peer (not in the paper): %s, %d bodies, %d frames of %.4f s, effects %s\n"
      "  Bullet's own: btGImpactMeshShape (%zu triangles per bunny, triangle margin %.3f m), "
      "btGImpactCollisionAlgorithm, btStaticPlaneShape ground,\n"
      "  btSequentialImpulseConstraintSolver (%d iterations), default friction/restitution, no swept-sphere CCD.\n",
      scene.name.c_str(), ours.bodyCount(), frames, scene.timestep, scene.effectList().c_str(),
      models.empty() ? std::size_t(0) : models[0]->meshInBody().triangles.size(), peer.margin(),
      peer.solverIterations());
  std::fflush(stdout);
  double cpu[2] = {0.0, 0.0};  // thread CPU time of the steps (s): ours, the peer
  double wall[2] = {0.0, 0.0};
  PenetrationSample deepest[2];
  for (int f = 0; f < frames; ++f) {
    for (int w = 0; w < 2; ++w) {
      const double cpuStart = threadCpuSeconds();
      const auto wallStart = std::chrono::steady_clock::now();
      if (w == 0) {
        ours.step();
      } else {
        peer.step();
      }
      wall[w] += std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
      cpu[w] += threadCpuSeconds() - cpuStart;
    }
    if (f % o.peerEvery != 0 && f + 1 != frames) continue;
    const PenetrationSample now[2] = {probe.measure(oursPoses()), probe.measure(peerPoses())};
    for (int w = 0; w < 2; ++w) {
      deepest[w].groundMetres = std::max(deepest[w].groundMetres, now[w].groundMetres);
      deepest[w].bodyMetres = std::max(deepest[w].bodyMetres, now[w].bodyMetres);
    }
    if ((f + 1) % 100 == 0) {
      std::fprintf(stderr, "  peer: frame %d/%d, step CPU ours %.2f s, GImpact %.2f s\n", f + 1, frames, cpu[0],
                   cpu[1]);
    }
  }
  const std::vector<int> tunneled[2] = {probe.tunneled(oursPoses()), probe.tunneled(peerPoses())};
  const double cell = probe.cellSize();
  std::printf("%-38s %16s %16s %9s\n", "", "ours (SdfccdShape)", "Bullet GImpact", "GImpact/ours");
  std::printf("%-38s %16.2f %16.2f %8.2fx\n", "step time, thread CPU (s)", cpu[0], cpu[1],
              cpu[0] > 0 ? cpu[1] / cpu[0] : 0.0);
  std::printf("%-38s %16.2f %16.2f %8.2fx\n", "step time, wall (s)", wall[0], wall[1],
              wall[0] > 0 ? wall[1] / wall[0] : 0.0);
  std::printf("%-38s %9.2f (%4.1f mm) %9.2f (%4.1f mm)\n", "max penetration into the ground, cells",
              deepest[0].groundMetres / cell, 1e3 * deepest[0].groundMetres, deepest[1].groundMetres / cell,
              1e3 * deepest[1].groundMetres);
  std::printf("%-38s %9.2f (%4.1f mm) %9.2f (%4.1f mm)\n", "max penetration body into body, cells",
              deepest[0].bodyMetres / cell, 1e3 * deepest[0].bodyMetres, deepest[1].bodyMetres / cell,
              1e3 * deepest[1].bodyMetres);
  std::printf("%-38s %16zu %16zu\n", "tunnelled bodies", tunneled[0].size(), tunneled[1].size());
  double clearanceMin[2] = {0.0, 0.0}, clearanceMax[2] = {0.0, 0.0};
  for (int w = 0; w < 2; ++w) {
    const std::vector<double> c = probe.clearance(w == 0 ? oursPoses() : peerPoses());
    if (c.empty()) continue;
    clearanceMin[w] = *std::min_element(c.begin(), c.end());
    clearanceMax[w] = *std::max_element(c.begin(), c.end());
  }
  std::printf("%-38s %7.1f .. %5.1f %9.1f .. %5.1f\n", "lowest vertex above ground at end, mm", 1e3 * clearanceMin[0],
              1e3 * clearanceMax[0], 1e3 * clearanceMin[1], 1e3 * clearanceMax[1]);
  std::printf(
      "Penetration: mesh vertices (%zu per bunny) below the ground and in the other bunny's field (cell %.2f mm), "
      "every %d frame(s); ours' own contact report (shell points): %.2f cells. The paper has no such figure.\n",
      models.empty() ? std::size_t(0) : models[0]->meshInBody().vertices.size(), 1e3 * cell, o.peerEvery,
      ours.maxPenetrationCells());
  const char* names[2] = {"ours", "gimpact"};
  for (int w = 0; w < 2; ++w) {
    csvRow("peer", names[w], "step_cpu_seconds", cpu[w]);
    csvRow("peer", names[w], "step_wall_seconds", wall[w]);
    csvRow("peer", names[w], "max_ground_penetration_cells", deepest[w].groundMetres / cell);
    csvRow("peer", names[w], "max_body_penetration_cells", deepest[w].bodyMetres / cell);
    csvRow("peer", names[w], "max_ground_penetration_m", deepest[w].groundMetres);
    csvRow("peer", names[w], "max_body_penetration_m", deepest[w].bodyMetres);
    csvRow("peer", names[w], "tunneled_bodies", double(tunneled[w].size()));
    csvRow("peer", names[w], "end_clearance_min_m", clearanceMin[w]);
    csvRow("peer", names[w], "end_clearance_max_m", clearanceMax[w]);
  }
  csvRow("peer", "frames", "frames", frames);
  csvRow("peer", "gimpact", "margin_m", peer.margin());
}

int runBenchBullet(BenchBulletOptions o) {
  const std::string parts[] = {"all", "table4", "fig10a", "peer", "modes", "stable", "scaling"};
  if (std::find(std::begin(parts), std::end(parts), o.part) == std::end(parts)) {
    throw Error("--part must be all, table4, fig10a, peer, modes, stable or scaling");
  }
  if (!(o.modes.maxPenetrationCells > 0)) throw Error("--max-penetration-cells must be > 0");
  if (!(o.modes.timingSeconds > 0) || !(o.modes.gimpactSeconds > 0)) {
    throw Error("--mode-seconds and --gimpact-seconds must be > 0");
  }
  o.modes.quick = o.quick;
  o.modes.scenes = o.scenes;
  o.modes.cache = o.cache;
  if (o.peerEvery < 1) throw Error("--peer-every must be >= 1");
  if (o.peerFrames < 0) throw Error("--peer-frames must be >= 0");
  if (o.forceTiming != "next_step" && o.forceTiming != "same_step") {
    throw Error("--force-timing must be next_step or same_step");
  }
  std::printf("sdfccd bench bullet%s -- %s\n", o.quick ? " --quick" : "", machineDescription().c_str());
  g_csv.str("");
  g_csv << "part,item,key,value\n";
  if (o.part == "all" || o.part == "table4") runTable4(o);
  if (o.part == "all" || o.part == "fig10a") runFig10a(o);
  if (o.part == "all" || o.part == "peer") runPeer(o);
  if (o.part == "all" || o.part == "modes") runModeTiming(o.modes, csvRow);
  if (o.part == "all" || o.part == "stable") runModeStability(o.modes, csvRow);
  if (o.part == "all" || o.part == "scaling") {
    ScalingBenchOptions scaling;
    scaling.quick = o.quick;
    scaling.scenes = o.scenes;
    scaling.cache = o.cache;
    scaling.plot = o.scalingPlot;
    scaling.bodies = o.scalingBodies;
    scaling.repeat = o.repeat;
    runScalingBench(scaling, csvRow);
  }
  if (!o.csv.empty()) {
    writeOutputFile(o.csv, g_csv.str());
    std::printf("wrote %s\n", o.csv.c_str());
  }
  return 0;
}

const BenchRegistrar bench_bulletRegistrar(
    "bullet",
    "Table 4 (CCD linear vs tree in drops), Fig. 10a (stability), the GImpact peer, "
    "the contact modes beside Bullet's shapes and their largest stable steps, the cost of piles of 20-320 "
    "bunnies on 1 and 2 threads (scaling)",
    [](CLI::App& sub) {
      auto o = std::make_shared<BenchBulletOptions>();
      sub.add_flag("--quick", o->quick, "A quarter of the frames, fewer timesteps");
      sub.add_option("--out", o->csv, "CSV output (default bench_bullet.csv; empty: none)");
      sub.add_option("--scenes", o->scenes, "Scene folder (default assets/scenes)")->check(nonEmpty());
      const CLI::Option* cache = addCacheOption(sub, o->cache, "Body model cache");
      sub.add_option("--part", o->part, "all, table4, fig10a, peer, modes, stable or scaling");
      sub.add_option("--scaling-plot", o->scalingPlot, "Scaling: the PNG (default bench_scaling.png; empty: none)");
      sub.add_option("--scaling-bodies", o->scalingBodies, "Scaling: pile sizes (default 20,80,320; --quick 4,12)")
          ->delimiter(',');
      sub.add_option("--repeat", o->repeat,
                     "Table 4 and scaling: runs of each measurement, in turns; the median is reported (default 1)")
          ->check(CLI::Range(1, 100));
      sub.add_option("--mode-seconds", o->modes.timingSeconds,
                     "Modes: simulated seconds per world (default 1; --quick 0.3)");
      sub.add_option("--gimpact-seconds", o->modes.gimpactSeconds,
                     "Modes: simulated seconds of the GImpact world (default 0.4)");
      sub.add_option("--max-penetration-cells", o->modes.maxPenetrationCells,
                     "Stable: the criterion's penetration bound in cells (default 8)");
      sub.add_option("--peer-every", o->peerEvery, "Peer: measure penetration every n-th frame (default 1)");
      sub.add_option("--peer-frames", o->peerFrames,
                     "Peer: frames to run (default 400, halved by --quick; 0: the scene's)");
      sub.add_option("--force-timing", o->forceTiming,
                     "Fig. 10a force timing: same_step (default) or next_step (the paper)");
      return std::function<int()>([o, cache]() {
        o->cache = resolveCacheOption(cache, o->cache);
        return runBenchBullet(*o);
      });
    });

}  // namespace
}  // namespace sdfccd::cli

#endif
