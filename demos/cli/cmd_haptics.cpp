/// @file
/// @brief `sdfccd haptics SCENE --method penalty|constraint|discrete-penalty|discrete-constraint
/// [--seconds S] [--out DIR] [--virtual-time] [--sim-cycles-per-tick N] [--ccd-threads N] [--no-passivity]
/// [--max-force-step N] [--rt-priority] [--cache DIR]`: a scripted,
/// headless 6-DoF haptics session (paper Section 4) with the emulated 1 kHz device.
///
/// @details Real time by default: the device loop runs at its rate on its own thread and, for the constraint
/// methods, the simulation loop runs as fast as it can on another (the paper's two asynchronous loops).
/// --virtual-time runs the same ticks back to back, deterministically (the simulation in lockstep).
/// Prints the summary JSON on stdout; with --out DIR also writes DIR/ticks.csv (one row per haptic tick:
/// device pose, simulation pose, force and torque on the device, contacts, penetration, QP state) and
/// DIR/summary.json, each atomically. Exit code 3 when the runaway guard stopped the session (the scene's "guard";
/// one line on stderr naming the body; the outputs are still written, for the post-mortem); exit code 4 when an
/// exception ended a loop (summary "error"; the device rendered zero from then on). The summary also reports the
/// device port's energy account (passivity.h), the force-rate limit's work, Colgate's stiffness bound and whether the
/// opt-in real-time priority was granted.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "cli/command_registry.h"
#include "haptics_experiments/session_output.h"
#include "sdfccd/error.h"
#include "sdfccd/haptics/haptic_session.h"
#include "sdfccd/model/model_cache_folder.h"
#include "sdfccd/output_file.h"
#include "sdfccd/output_folder.h"

namespace sdfccd::cli {
namespace {

struct HapticsOptions {
  std::string scene;
  std::string method = "constraint";
  double seconds = 0.0;
  std::string out;
  bool virtualTime = false;
  int simCyclesPerTick = 1;
  int ccdThreads = 1;
  bool noPassivity = false;
  bool realTimePriority = false;
  double maxForceStep = -1.0;  // < 0: the session's default
  std::string cache;
  const CLI::Option* cacheOption = nullptr;  // given: --cache wins, even "" (no cache)
};

int runHaptics(const HapticsOptions& o) {
  haptics::HapticSessionSettings settings;
  settings.method = haptics::parseHapticMethod(o.method);
  // Written so that NaN fails too (every comparison with NaN is false); 0 means the scene's length.
  if (!(o.seconds >= 0.0 && o.seconds <= 3600.0)) throw Error("--seconds must be in (0, 3600]");
  if (o.simCyclesPerTick < 1 || o.simCyclesPerTick > 1000) throw Error("--sim-cycles-per-tick must be in 1..1000");
  if (o.ccdThreads < 1 || o.ccdThreads > 256) throw Error("--ccd-threads must be in 1..256");
  settings.seconds = o.seconds;
  settings.realTime = !o.virtualTime;
  settings.simCyclesPerTick = o.simCyclesPerTick;
  settings.ccdThreads = o.ccdThreads;
  settings.recordTicks = !o.out.empty();
  settings.passivityEnabled = !o.noPassivity;
  if (o.maxForceStep >= 0.0) settings.passivity.maxForceStep = o.maxForceStep;
  if (o.realTimePriority && o.virtualTime) throw Error("--rt-priority needs real time (not --virtual-time)");
  settings.realTimePriority = o.realTimePriority;
  haptics::HapticSceneLoadSettings load;
  load.cacheDir = modelCacheFolder(o.cacheOption->count() > 0 ? &o.cache : nullptr);
  checkModelCacheWritable(load.cacheDir);  // before the build, not after it
  const haptics::HapticScene scene = haptics::loadHapticScene(o.scene, load);
  std::optional<OutputFolder> outFolder;  // removed again if the session fails and it was made for it
  if (!o.out.empty()) {
    outFolder.emplace(o.out);
    checkOutput(o.out + "/ticks.csv", {o.scene});
    checkOutput(o.out + "/summary.json", {o.scene});
  }
  haptics::HapticSessionResult result = haptics::runHapticSession(scene, settings);
  // The scene file, for `sdfccd render`/`plot` of the run folder (they reload the tool's mesh and the obstacle).
  result.summary.sceneFile = std::filesystem::absolute(o.scene).lexically_normal().string();
  const std::string summary = haptics::summaryJson(result.summary);
  if (outFolder) {
    haptics::writeTickCsv(o.out + "/ticks.csv", result.ticks);
    writeOutputFile(o.out + "/summary.json", summary);
    outFolder->keep();
  }
  std::fwrite(summary.data(), 1, summary.size(), stdout);
  std::fflush(stdout);
  if (!result.summary.error.empty()) {
    // An exception in a loop: the device rendered zero from that tick on and both loops were joined.
    std::fprintf(stderr, "haptics: the session failed (device force set to zero): %s\n", result.summary.error.c_str());
    return 4;
  }
  if (result.summary.guardStopped) {
    // The runaway guard (scene key "guard"): the device rendered zero force from that tick on and the loop ended.
    std::fprintf(stderr, "haptics: runaway stopped the session (device force set to zero): %s\n",
                 result.summary.runaway.c_str());
    return 3;
  }
  if (!result.summary.runaway.empty()) {
    std::fprintf(stderr, "haptics: runaway reported (guard action \"report\"): %s\n", result.summary.runaway.c_str());
  }
  return 0;
}

const CommandRegistrar cmd_hapticsRegistrar("haptics", [](CLI::App& app) {
  auto o = std::make_shared<HapticsOptions>();
  CLI::App* cmd = app.add_subcommand("haptics", "Scripted headless 6-DoF haptics session (emulated 1 kHz device)");
  cmd->add_option("scene", o->scene, "Haptic scene file (assets/scenes/haptics/*.json)")->required();
  cmd->add_option("--method", o->method, "penalty, constraint (default), discrete-penalty or discrete-constraint");
  cmd->add_option("--seconds", o->seconds, "Session length in seconds (default: the scene's)");
  cmd->add_option("--out", o->out, "Output folder for ticks.csv and summary.json");
  cmd->add_flag("--virtual-time", o->virtualTime, "Deterministic: no sleeping, simulation in lockstep");
  cmd->add_option("--sim-cycles-per-tick", o->simCyclesPerTick, "Virtual time: simulation cycles per tick (1)");
  cmd->add_option("--ccd-threads", o->ccdThreads, "CCD worker threads (1)");
  cmd->add_flag("--no-passivity", o->noPassivity,
                "Without the device port's passivity controller and force-rate limit (the observer still reports)");
  cmd->add_option("--max-force-step", o->maxForceStep, "Force-rate limit, N per tick (default 1; 0: none)")
      ->check(CLI::Range(0.0, 1e6));
  cmd->add_flag("--rt-priority", o->realTimePriority,
                "Ask for SCHED_FIFO for the haptic loop (opt-in; the summary says whether it was granted)");
  o->cacheOption = cmd->add_option("--cache", o->cache,
                                   "Cache of fields built from meshes (\"\" disables; default $XDG_CACHE_HOME/sdfccd, "
                                   "else ~/.cache/sdfccd)");
  return std::function<int()>([o]() { return runHaptics(*o); });
});

}  // namespace
}  // namespace sdfccd::cli
