/// @file
/// @brief Report section `effects`: an effect a scene does not ask for costs nothing (scene effects as in scene.h:
/// gravity, ground, damping, rotation, friction).
///
/// @details One scene, ten bunnies of assets/scenes/drop-bunnies.json (the paper's Fig. 10a bunnies: 777 points,
/// 128^3 fields; 64^3 in smoke mode) thrown down at 1 m/s, the upper layer at 2 m/s so that it catches the lower
/// one, spinning: every effect has contacts to act on even without gravity or ground. The scene runs with no
/// effect, with each effect alone, and with all of them. Per run: the step time (thread CPU time per frame, the
/// median over repeats; bodies never sleep) and work counters of the contact system (ContactStatistics):
/// CCD queries against the ground plane, damping terms, torques, friction terms evaluated, and the gravity in
/// the world. The section is ok when every counter of an effect that is off is zero and every effect that is on
/// alone did some work.
#if __has_include("sdfccd/bullet/scene_world.h")  // built only with the Bullet plugin
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli/line_plot.h"
#include "cli/markdown_table.h"
#include "cli/report_registry.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/error.h"
#include "sdfccd/output_file.h"
#include "sdfccd/thread_cpu_time.h"

namespace sdfccd::cli {
namespace {

const char* const kEffects[] = {"gravity", "ground", "damping", "rotation", "friction"};
constexpr std::size_t kEffectCount = 5;

/// One configuration's measurements.
struct EffectsRun {
  std::string name;
  std::set<std::string> effects;
  double stepMilliseconds = 0.0;            ///< median over repeats of the mean thread CPU time per frame
  double ccdMilliseconds = 0.0;             ///< CCD part of it (same run as the median)
  double groundCcdMilliseconds = 0.0;       ///< of the CCD, against the ground plane
  std::array<double, kEffectCount> work{};  ///< per effect, in kEffects order (see workOf)
  std::int64_t penaltySamples = 0;
  std::int64_t contactQueries = 0;
};

/// The scene: bodies 0-4 and 10-14 of drop-bunnies (two layers), thrown down and spinning.
Scene effectsScene(const ReportContext& context, int frames) {
  Scene scene = loadScene((context.assetsDir / "scenes" / "drop-bunnies.json").string());
  std::vector<SceneBody> bodies;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    if (!(i < 5 || (i >= 10 && i < 15))) continue;
    SceneBody b = scene.bodies[i];
    const bool upper = i >= 10;
    b.velocity = Vec3(0.0, upper ? -2.0 : -1.0, 0.0);
    b.angularVelocity = Vec3(upper ? 3.0 : -3.0, 2.0, 0.0);
    if (context.smoke) b.resolution = 64;
    bodies.push_back(b);
  }
  if (bodies.size() != 10) throw Error("effects: drop-bunnies.json no longer has 20 bodies");
  scene.bodies = bodies;
  scene.frames = frames;
  scene.sleeping = false;
  return scene;
}

EffectsRun runOnce(const Scene& base, const std::string& name, const std::set<std::string>& effects,
                   const ReportContext& context, int repeats, const std::function<void()>& repeatDone) {
  EffectsRun run;
  run.name = name;
  run.effects = effects;
  Scene scene = base;
  scene.effects = effects;
  std::vector<std::array<double, 3>> times;  // (step, ccd, ground ccd) ms per frame
  for (int r = 0; r < repeats; ++r) {
    bullet::SceneWorldSettings settings;
    settings.cacheDir = context.cacheDir.string();
    settings.threads = context.threads;
    settings.allowSleeping = false;
    bullet::SceneWorld world(scene, settings);
    const double start = threadCpuSeconds();
    for (int f = 0; f < scene.frames; ++f) world.step();
    const double seconds = threadCpuSeconds() - start;
    if (world.hasNonFinite()) throw Error("effects: the run '" + name + "' produced NaN or infinite states");
    const bullet::ContactStatistics& stats = world.contacts().statistics();
    times.push_back({1e3 * seconds / scene.frames, 1e3 * stats.ccdSeconds / scene.frames,
                     1e3 * stats.groundCcdSeconds / scene.frames});
    // Counters are deterministic (same scene, same steps): the last repeat's stand for all.
    run.work[0] = double(world.world().getGravity().length());
    run.work[1] = double(stats.groundCcdQueries);
    run.work[2] = double(stats.dampingEvaluations);
    run.work[3] = double(stats.torqueEvaluations);
    run.work[4] = double(stats.frictionEvaluations);
    run.penaltySamples = stats.penaltySamples;
    run.contactQueries = stats.ccdQueries;
    repeatDone();
  }
  std::sort(times.begin(), times.end());
  run.stepMilliseconds = times[times.size() / 2][0];
  run.ccdMilliseconds = times[times.size() / 2][1];
  run.groundCcdMilliseconds = times[times.size() / 2][2];
  return run;
}

ReportSection runEffectsSection(const ReportContext& context) {
  const int frames = context.smoke ? 60 : context.quick ? 500 : 2000;
  const int repeats = context.smoke ? 1 : context.quick ? 3 : 5;
  const Scene base = effectsScene(context, frames);

  std::vector<std::pair<std::string, std::set<std::string>>> configs;
  configs.push_back({"none", {}});
  for (const char* e : kEffects) configs.push_back({std::string(e) + " alone", {e}});
  configs.push_back({"all", {kEffects, kEffects + kEffectCount}});

  const double total = static_cast<double>(configs.size() * static_cast<std::size_t>(repeats));
  double done = 0.0;
  std::vector<EffectsRun> runs;
  for (const auto& [name, effects] : configs) {
    runs.push_back(runOnce(base, name, effects, context, repeats, [&]() { context.progress(++done / total); }));
  }

  // Verdict: off means zero work; on alone means some work (else the counter proves nothing).
  bool ok = true;
  std::string problems;
  for (const EffectsRun& run : runs) {
    for (std::size_t e = 0; e < kEffectCount; ++e) {
      const bool on = run.effects.count(kEffects[e]) != 0;
      if (!on && run.work[e] != 0.0) {
        ok = false;
        problems += std::string("**") + kEffects[e] + " did work while off in '" + run.name + "'.** ";
      }
      if (on && run.effects.size() == 1 && !(run.work[e] > 0.0)) {
        ok = false;
        problems += std::string("**") + kEffects[e] + " did no work while on in '" + run.name +
                    "' (the scene does not exercise it).** ";
      }
    }
  }

  const double none = runs.front().stepMilliseconds;
  std::ostringstream table, csv;
  table << "| Run | Step (ms) | vs none | CCD (ms) | Ground CCD (ms) | Gravity in the world (m/s^2) | Ground CCD "
           "queries | Damping "
           "terms | Torques | Friction terms | Penalty samples "
           "|\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  csv << "run,effects,step_ms,ccd_ms,ground_ccd_ms,gravity,ground_ccd_queries,damping_evaluations,torque_evaluations,"
         "friction_evaluations,penalty_samples,ccd_queries,frames,repeats\n";
  PlotSeries stepSeries{"step (thread CPU)", {}, {}};
  PlotSeries ccdSeries{"of it, CCD", {}, {}};
  std::vector<std::string> categories;
  for (const EffectsRun& run : runs) {
    std::string effects;
    for (const std::string& e : run.effects) effects += (effects.empty() ? "" : ";") + e;
    table << "| " << run.name << " | " << fmt("%.3f", run.stepMilliseconds) << " | "
          << fmt("%.2f", run.stepMilliseconds / std::max(none, 1e-12)) << "x | " << fmt("%.3f", run.ccdMilliseconds)
          << " | " << fmt("%.3f", run.groundCcdMilliseconds) << " | " << fmt("%.2f", run.work[0]);
    for (std::size_t e = 1; e < kEffectCount; ++e) table << " | " << fmt("%.0f", run.work[e]);
    table << " | " << run.penaltySamples << " |\n";
    csv << run.name << ',' << effects << ',' << run.stepMilliseconds << ',' << run.ccdMilliseconds << ','
        << run.groundCcdMilliseconds;
    for (double w : run.work) csv << ',' << w;
    csv << ',' << run.penaltySamples << ',' << run.contactQueries << ',' << frames << ',' << repeats << '\n';
    categories.push_back(run.name);
    stepSeries.y.push_back(run.stepMilliseconds);
    ccdSeries.y.push_back(run.ccdMilliseconds);
  }
  writeOutputFile((context.outDir / "effects.csv").string(), csv.str());
  LinePlot plot;
  plot.title = "Step time with each effect alone (10 bunnies, 777 points each)";
  plot.xLabel = "effects simulated";
  plot.yLabel = "ms per frame (one core)";
  plot.style = PlotStyle::Bars;
  plot.categories = categories;
  plot.series = {stepSeries, ccdSeries};
  plot.width = 1000;
  writeLinePlot(plot, context.outDir / "effects_step_time.png");

  std::ostringstream md;
  md << "## Effects: what a scene does not ask for costs nothing\n\n"
     << "A scene lists the effects it simulates (gravity, ground, damping, rotation, friction; docs/scene-format.md \""
        "Effects\"); an effect not listed is not simulated at all, rather than simulated with a zero coefficient. "
        "Scene: ten bunnies of `drop-bunnies.json` (777 points, "
     << base.bodies.front().resolution
     << "^3 fields), thrown down at 1 m/s (upper layer 2 m/s, so it catches the lower one) and spinning, so every "
        "effect has contacts to act on; "
     << frames << " frames of " << fmt("%.0f", 1e3 * base.timestep)
     << " ms, bodies never sleep. Step: thread CPU time per frame, median of " << repeats
     << " run(s). The counters are the contact system's work: CCD queries against the ground plane, damping "
        "terms, torques and friction terms evaluated at the penalty samples (ContactStatistics). The paper "
        "has no figure for this (its scenes always simulate every effect).\n\n"
     << table.str() << "\n"
     << (ok ? "Every counter of an effect that is off is zero in every run, and each effect alone does work: an "
              "effect costs time only when the scene asks for it. Step times differ between runs mostly because "
              "the motion differs (with the ground, bodies stop and stay in contact; without it they fly on "
              "after their collisions; a rotating body sweeps longer paths)."
            : problems)
     << "\n\n![Step time per effect](effects_step_time.png)\n\n"
     << "Data: `effects.csv`.\n";
  return {md.str(), ok};
}

const ReportRegistrar bullet_effectsRegistrar(60, "effects", "Effects: what a scene does not ask for costs nothing",
                                              runEffectsSection);

}  // namespace
}  // namespace sdfccd::cli

#endif
