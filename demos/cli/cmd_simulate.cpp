/// @file
/// @brief `sdfccd simulate SCENE [--frames N] [--out DIR]`: runs a scene headless in Bullet with the
/// continuous penalty contact of Section 4.1 (or the discrete baseline), writing a run folder: frames.csv
/// (wide layout: one row per frame, `<body>.px` ... `<body>.wz` at the centre of mass, then contacts,
/// penetration in cells, kinetic_energy in J, ccd_seconds, step_seconds, clamps; body names quoted as CSV
/// fields when they need it; every K-th frame with --record-every K), summary.json and scene.json. A run that
/// fails or is interrupted leaves no temporary file and no run folder it created empty.
#if __has_include("sdfccd/bullet/scene_world.h")

#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cli/command_registry.h"
#include "cli/csv_fields.h"
#include "cli/progress_bar.h"
#include "cli/run_frame_renderer.h"
#include "sdfccd/bullet/contact_solver.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/error.h"
#include "sdfccd/model/model_cache_folder.h"
#include "sdfccd/model/runaway_guard.h"
#include "sdfccd/output_file.h"
#include "sdfccd/output_folder.h"

namespace sdfccd::cli {
namespace {

struct SimulateOptions {
  std::string scene;
  int frames = 0;  // 0: the scene's
  int recordEvery = 1;
  std::string out;
  std::string cache;
  const CLI::Option* cacheOption = nullptr;  // given: --cache wins, even "" (no cache)
  std::string model;
  double timestep = 0.0;
  double stiffness = 0.0;
  bool noToi = false;
  bool linear = false;
  int threads = 0;  // narrowphase threads (0: all hardware threads)
  std::string forceTiming;
  std::string renderDir;  // --render: frames of the run as PNG
  int renderEvery = 10;
  std::string renderSize = "960x540";
};

std::string hex(std::uint64_t v) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

/// The scene's name as shown on the terminal: control characters (a newline, an escape sequence) become '?',
/// so a scene file cannot forge output lines or drive the terminal.
std::string shownName(const std::string& name) {
  std::string out = name;
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  }
  return out;
}

/// The bodies' centre-of-mass motion as the runaway guard reads it.
std::vector<GuardBodyState> guardStates(const bullet::SceneWorld& world) {
  std::vector<GuardBodyState> states;
  for (int i = 0; i < world.bodyCount(); ++i) {
    const bullet::SceneBodyState s = world.bodyState(i);
    states.push_back({s.position, s.linearVelocity});
  }
  return states;
}

int runSimulate(const SimulateOptions& o) {
  const auto wallStart = std::chrono::steady_clock::now();
  const Scene scene = loadScene(o.scene);
  if (o.frames < 0) throw Error("--frames must be >= 0");
  if (o.recordEvery < 1) throw Error("--record-every must be at least 1");
  const int frames = o.frames > 0 ? o.frames : scene.frames;
  // The run folder's copy of the scene is the text that ran (read now: the file may be the run folder's own
  // scene.json, which is then rewritten with the same text).
  std::string sceneText;
  {
    std::ifstream sceneFile(o.scene, std::ios::binary);
    std::ostringstream text;
    text << sceneFile.rdbuf();
    sceneText = text.str();
  }
  // The scene's name is data: the default run folder gets a sanitized copy (sceneFolderName), never a path
  // the file chooses ("../../x" stays inside out/simulate/).
  const std::string outDir = o.out.empty() ? "out/simulate/" + sceneFolderName(scene.name) : o.out;
  OutputFolder runFolder(outDir);
  // Outputs that are the scene, or cannot be written, fail now, not after the build and the run.
  checkOutput(outDir + "/frames.csv", {o.scene});
  checkOutput(outDir + "/summary.json", {o.scene});

  bullet::SceneWorldSettings settings;
  settings.cacheDir = modelCacheFolder(o.cacheOption->count() > 0 ? &o.cache : nullptr);
  checkModelCacheWritable(settings.cacheDir);  // before the build, not after it
  if (!o.model.empty()) {
    if (o.model == "continuous") {
      settings.model = PenaltyModel::Continuous;
    } else if (o.model == "discrete") {
      settings.model = PenaltyModel::Discrete;
    } else {
      throw Error("--model must be continuous or discrete (got '" + o.model + "')");
    }
  }
  // Overrides get the ranges the scene file's keys get (a --timestep 5 is as absurd as a "timestep": 5).
  if (o.timestep != 0.0) {
    if (!(o.timestep >= 1e-7 && o.timestep <= 1.0)) throw Error("--timestep must be in [1e-07, 1] s");
    settings.timestep = o.timestep;
  }
  if (o.stiffness != 0.0) {
    if (!(o.stiffness > 0.0 && o.stiffness <= 1e9)) throw Error("--stiffness must be in (0, 1e+09] N/m");
    settings.stiffness = o.stiffness;
  }
  if (settings.model == PenaltyModel::Discrete && scene.contact.mode == SdfccdContactMode::Solver) {
    throw Error("--model discrete applies to penalty mode only (the scene's contact.mode is solver)");
  }
  if (o.noToi) settings.timeOfImpactClamp = false;
  if (o.linear) settings.useTree = false;
  if (o.threads < 0 || o.threads > bullet::kMaxNarrowphaseThreads)
    throw Error("--threads must be in 0.." + std::to_string(bullet::kMaxNarrowphaseThreads) +
                " (0: all hardware threads; got " + std::to_string(o.threads) + ")");
  settings.narrowphaseThreads = o.threads;
  if (o.forceTiming == "next_step") {
    settings.forceTiming = ForceTiming::NextStep;
  } else if (o.forceTiming == "same_step") {
    settings.forceTiming = ForceTiming::SameStep;
  } else if (!o.forceTiming.empty()) {
    throw Error("--force-timing must be same_step or next_step (got '" + o.forceTiming + "')");
  }

  std::unique_ptr<bullet::SceneWorld> world;
  {
    ProgressBar bar("building " + shownName(scene.name));
    settings.buildProgress = bar.callback();
    world = std::make_unique<bullet::SceneWorld>(scene, settings);
  }
  const double buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();

  OutputFile csv(outDir + "/frames.csv");
  std::ostream& out = csv.stream();
  out << std::setprecision(9);
  out << "frame,time";
  for (int i = 0; i < world->bodyCount(); ++i) {
    const std::string& n = world->bodyName(i);
    for (const char* c : {"px", "py", "pz", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz"}) {
      out << "," << csvField(n + "." + c);
    }
  }
  out << ",contacts,penetration,kinetic_energy,ccd_seconds,step_seconds,clamps\n";

  // Frames are rendered while simulating (the same camera and names as `sdfccd render` of the run folder).
  std::unique_ptr<RunFrameRenderer> frameRenderer;
  if (!o.renderDir.empty()) {
    frameRenderer = makeSceneFrameRenderer(o.scene, o.renderSize, o.renderEvery, o.renderDir);
  }
  auto renderFrame = [&](int frame) {
    if (!frameRenderer || !frameRenderer->wantsFrame(frame)) return;
    std::vector<Rigid> poses;
    for (int i = 0; i < world->bodyCount(); ++i) {
      const bullet::SceneBodyState s = world->bodyState(i);
      poses.push_back(bodyPose(s.position, s.orientation));
    }
    frameRenderer->renderRunFrame(frame, poses, o.renderDir);
  };
  renderFrame(0);

  bool nan = false;
  int done = 0;
  auto recordFrame = [&] {
    out << done << "," << world->time();
    for (int i = 0; i < world->bodyCount(); ++i) {
      const bullet::SceneBodyState s = world->bodyState(i);
      out << "," << s.position.x() << "," << s.position.y() << "," << s.position.z() << "," << s.orientation.w() << ","
          << s.orientation.x() << "," << s.orientation.y() << "," << s.orientation.z() << "," << s.linearVelocity.x()
          << "," << s.linearVelocity.y() << "," << s.linearVelocity.z() << "," << s.angularVelocity.x() << ","
          << s.angularVelocity.y() << "," << s.angularVelocity.z();
    }
    const bullet::SceneFrameStats& last = world->lastFrame();
    out << "," << last.contacts << "," << last.penetrationCells << "," << world->kineticEnergy() << ","
        << last.ccdSeconds << "," << last.stepSeconds << "," << last.clamps << "\n";
  };
  // The runaway watchdog (runaway_guard.h): an exploded state stops the run like a NaN does, exit code 3.
  const RunawayGuard guard(world->scene(), world->kineticEnergy());
  std::optional<std::string> runaway;  // the first violation
  int runawayFrame = 0;
  bool guardStopped = false;
  {
    ProgressBar bar("simulating " + shownName(scene.name));
    for (int f = 0; f < frames; ++f) {
      world->step();
      ++done;
      const bool nonFinite = world->hasNonFinite();
      if (!nonFinite && !runaway) {
        runaway = guard.check(world->time(), guardStates(*world), world->kineticEnergy());
        if (runaway) runawayFrame = done;
        guardStopped = runaway && world->scene().guard.action == GuardAction::Stop;
      }
      // Every K-th frame, the last one, and the one that went non-finite or ran away.
      if (done % o.recordEvery == 0 || done == frames || nonFinite || guardStopped) recordFrame();
      bar.update(double(done) / frames);
      if (nonFinite) {
        nan = true;
        break;
      }
      if (guardStopped) break;
      renderFrame(done);
    }
  }
  csv.commit();
  writeOutputFile(outDir + "/scene.json", sceneText);  // the run folder carries its scene (render, plot)

  const double wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
  const std::vector<std::string> tunneled = world->tunneledBodies();
  nlohmann::ordered_json summary;
  summary["scene"] = o.scene;
  summary["frames"] = done;
  summary["record_every"] = o.recordEvery;
  summary["timestep"] = world->timestep();
  // The mode decides who answers the contacts; the model (continuous/discrete) exists in penalty mode only, the
  // constraint solver (contact.solver) in solver mode only.
  const SceneContact& contact = world->scene().contact;
  const bool solverMode = contact.mode == SdfccdContactMode::Solver;
  summary["mode"] = solverMode ? "solver" : "penalty";
  if (solverMode) {
    summary["solver"] = bullet::contactSolverName(contact.solver);
  } else {
    summary["model"] = contact.model == PenaltyModel::Continuous ? "continuous" : "discrete";
  }
  summary["stiffness"] = world->scene().contact.stiffness;
  summary["time_of_impact_clamp"] = world->scene().contact.timeOfImpactClamp;
  summary["point_tree"] = world->scene().contact.useTree;
  summary["bodies"] = world->bodyCount();
  summary["active_effects"] = std::vector<std::string>(scene.effects.begin(), scene.effects.end());
  summary["wall_seconds"] = wallSeconds;
  summary["build_seconds"] = buildSeconds;
  summary["step_seconds"] = world->stepSeconds();
  summary["ccd_seconds"] = world->ccdSeconds();
  summary["max_penetration_cells"] = world->maxPenetrationCells();
  summary["clamps"] = world->clamps();
  summary["tunneled_bodies"] = tunneled.size();
  summary["tunneled_names"] = tunneled;
  summary["nan_detected"] = nan;
  summary["final_kinetic_energy"] = nan ? 0.0 : world->kineticEnergy();
  summary["runaway_detected"] = runaway.has_value();
  summary["runaway"] = runaway ? *runaway : std::string();
  summary["runaway_frame"] = runawayFrame;
  summary["guard_stopped"] = guardStopped;
  summary["result_hash"] = hex(world->stateHash());
  writeOutputFile(outDir + "/summary.json", summary.dump(2) + "\n");
  runFolder.keep();

  const std::string how = solverMode ? "solver mode (" + summary["solver"].get<std::string>() + " solver)"
                                     : "penalty mode, " + summary["model"].get<std::string>() + " model";
  std::printf("%s: %d frames of %g s, %d bodies, %s, effects [%s]\n", shownName(scene.name).c_str(), done,
              world->timestep(), world->bodyCount(), how.c_str(), scene.effectList().c_str());
  std::printf(
      "wall %.2f s (build %.2f s, steps %.2f s, CCD %.2f s); max penetration %.3f cells; %zu tunnelled; "
      "%s; final kinetic energy %.6g J\n",
      wallSeconds, buildSeconds, world->stepSeconds(), world->ccdSeconds(), world->maxPenetrationCells(),
      tunneled.size(), nan ? "NaN DETECTED" : (runaway ? "RUNAWAY (guard)" : "no NaN"),
      summary["final_kinetic_energy"].get<double>());
  std::printf("wrote %s/frames.csv and %s/summary.json\n", shownName(outDir).c_str(), shownName(outDir).c_str());
  // A failed run says so on stderr (one line), besides the NaN/summary lines on stdout.
  if (nan) {
    std::fprintf(stderr, "sdfccd: error: simulate: scene '%s': the state went non-finite (NaN) at frame %d\n",
                 shownName(o.scene).c_str(), done);
    return 3;
  }
  if (guardStopped) {
    std::fprintf(stderr, "sdfccd: error: simulate: scene '%s': runaway stopped at frame %d: %s\n",
                 shownName(o.scene).c_str(), runawayFrame, shownName(*runaway).c_str());
    return 3;
  }
  return 0;
}

const CommandRegistrar cmd_simulateRegistrar("simulate", [](CLI::App& app) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand("simulate", "Run a scene (assets/scenes/*.json) headless in Bullet");
  cmd->add_option("scene", o->scene, "Scene file (JSON)")->required();
  cmd->add_option("--frames", o->frames, "Frames to run (default: the scene's)");
  cmd->add_option("--record-every", o->recordEvery,
                  "Write every K-th frame (and the last) to frames.csv, for long runs (default 1)");
  cmd->add_option("--out", o->out, "Output folder (default: out/simulate/<scene name>)");
  o->cacheOption = cmd->add_option("--cache", o->cache,
                                   "Body model cache folder (\"\" disables; default $XDG_CACHE_HOME/sdfccd, else "
                                   "~/.cache/sdfccd)");
  cmd->add_option("--model", o->model, "Override the contact model: continuous or discrete");
  cmd->add_option("--timestep", o->timestep, "Override the timestep (s)");
  cmd->add_option("--stiffness", o->stiffness, "Override the contact stiffness (N/m per point)");
  cmd->add_flag("--no-toi", o->noToi, "Disable time-of-impact clamping");
  cmd->add_flag("--linear", o->linear, "Point-by-point CCD instead of the point tree");
  cmd->add_option("--render", o->renderDir, "Also write frame_%05d.png of the run into this folder");
  cmd->add_option("--every", o->renderEvery, "With --render: every K-th frame (default 10)");
  cmd->add_option("--size", o->renderSize, "With --render: frame size WIDTHxHEIGHT (default 960x540)");
  cmd->add_option("--force-timing", o->forceTiming, "Override contact.force_timing: same_step or next_step");
  cmd->add_option("--threads", o->threads,
                  "Narrowphase threads: the pairs' CCD on a pool (default 0: all hardware threads; 1: serial; "
                  "results are identical for every value)");
  return std::function<int()>([o]() { return runSimulate(*o); });
});

}  // namespace
}  // namespace sdfccd::cli

#endif
