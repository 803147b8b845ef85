/// @file
/// @brief The contact modes beside Bullet's own shapes (see bullet_mode_bench.h).
#include "bench/bullet_mode_bench.h"

#if __has_include("sdfccd/bullet/scene_world.h")  // built only with the Bullet plugin
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <vector>

#include "bench/gimpact_peer.h"
#include "bench/penetration_probe.h"
#include "sdfccd/bullet/scene_world.h"
#include "sdfccd/model/runaway_guard.h"
#include "sdfccd/thread_cpu_time.h"

namespace sdfccd::cli {
namespace {

constexpr double kSolverStep = 1.0 / 240.0;  // s: Bullet's usual fixed step
constexpr double kPenaltyStep = 0.001;       // s: the paper's step
// s of simulated time between penetration samples: each sample looks up every mesh vertex (20 x 37,000 for the
// bunnies) in the neighbours' fields, which costs more than a step, so --quick samples less often.
double probeInterval(const ModeBenchOptions& o) {
  return o.quick ? 0.005 : 0.002;
}

/// One world of the comparison, behind a common face.
struct Contender {
  std::string name;
  double timestep = 0.0;
  std::function<void()> step;
  std::function<std::vector<Rigid>()> poses;  ///< body frames (centre of mass), scene order
  std::function<double()> kinetic;
  std::function<bool()> nonFinite;
};

/// What one run of a contender measured.
struct ContenderRun {
  int frames = 0;
  double cpuSeconds = 0.0;    ///< thread CPU time of the steps alone
  double groundMetres = 0.0;  ///< deepest mesh vertex below the ground over the run
  double bodyMetres = 0.0;    ///< deepest mesh vertex inside another body over the run
  double energyGain = 0.0;    ///< largest total energy above the start (J)
  int tunneled = 0;
  std::string why;  ///< "" or why the run is unstable
};

/// The shared pieces of one benchmark scene: the scene, the models (built once, by a SceneWorld) and the probe.
struct BenchScene {
  std::string label;
  Scene scene;
  std::vector<std::shared_ptr<const BodyModel>> models;
  std::unique_ptr<PenetrationProbe> probe;
};

BenchScene loadBenchScene(const ModeBenchOptions& o, const std::string& label, const std::string& file) {
  BenchScene b;
  b.label = label;
  b.scene = loadScene(o.scenes + "/" + file);
  bullet::SceneWorldSettings settings;
  settings.cacheDir = o.cache;
  const bullet::SceneWorld world(b.scene, settings);
  std::vector<bool> isStatic;
  for (int i = 0; i < world.bodyCount(); ++i) {
    b.models.push_back(world.modelPtr(i));
    isStatic.push_back(world.isStatic(i));
  }
  const Scene& s = b.scene;
  b.probe = std::make_unique<PenetrationProbe>(b.models, isStatic,
                                               s.has("ground") ? std::optional<double>(s.groundHeight) : std::nullopt);
  return b;
}

/// Our world in `mode` at `dt`; `contact`: the scene's contact keys (nullopt: the project's defaults).
/// `solver`: Bullet's constraint solver in solver mode (nullopt: the scene's contact.solver).
Contender oursContender(const ModeBenchOptions& o, const BenchScene& b, const std::string& name, SdfccdContactMode mode,
                        double dt, bool keepSceneContact, std::optional<ContactSolver> solver = std::nullopt) {
  Scene scene = b.scene;
  if (!keepSceneContact) scene.contact = SceneContact{};  // a new world's defaults
  scene.contact.mode = mode;
  scene.timestep = dt;
  bullet::SceneWorldSettings settings;
  settings.cacheDir = o.cache;
  settings.solver = solver;
  auto world = std::make_shared<bullet::SceneWorld>(scene, settings);
  Contender c;
  c.name = name;
  c.timestep = dt;
  c.step = [world]() { world->step(); };
  c.poses = [world]() {
    std::vector<Rigid> poses;
    for (int i = 0; i < world->bodyCount(); ++i) {
      const bullet::SceneBodyState s = world->bodyState(i);
      Rigid r = Rigid::Identity();
      r.linear() = s.orientation.normalized().toRotationMatrix();
      r.translation() = s.position;
      poses.push_back(r);
    }
    return poses;
  };
  c.kinetic = [world]() { return world->kineticEnergy(); };
  c.nonFinite = [world]() { return world->hasNonFinite(); };
  return c;
}

Contender peerContender(const BenchScene& b, const std::string& name, PeerShape shape, double dt) {
  auto peer = std::make_shared<GImpactPeer>(b.scene, b.models, shape, dt);
  Contender c;
  c.name = name;
  if (peer->hullVertices() > 0) std::printf("  (the convex hull has %d vertices)\n", peer->hullVertices());
  c.timestep = dt;
  c.step = [peer]() { peer->step(); };
  c.poses = [peer]() {
    std::vector<Rigid> poses;
    for (int i = 0; i < peer->bodyCount(); ++i) poses.push_back(peer->worldFromBody(i));
    return poses;
  };
  c.kinetic = [peer]() { return peer->kineticEnergy(); };
  c.nonFinite = [peer]() { return peer->hasNonFinite(); };
  return c;
}

/// Kinetic + gravitational potential energy of the dynamic bodies (J).
double totalEnergy(const BenchScene& b, Contender& c) {
  const double g = b.scene.has("gravity") ? -b.scene.gravity.y() : 0.0;
  const std::vector<Rigid> poses = c.poses();
  double e = c.kinetic();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!b.scene.bodies[i].isStatic) e += b.scene.bodies[i].mass * g * poses[i].translation().y();
  }
  return e;
}

/// Steps `c` for `seconds` of simulated time, timing the steps and probing penetration every probeEverySeconds; with
/// `maxCells` > 0 stops at the first breach of kModeStabilityCriterion.
ContenderRun runContender(const BenchScene& b, Contender& c, double seconds, double maxCells,
                          double probeEverySeconds) {
  ContenderRun run;
  const double start = totalEnergy(b, c);
  const double cell = b.probe->cellSize();
  // The runaway guard in report mode: a violation makes the run unstable ("runaway") instead of ending the
  // program. Velocities are the centres' finite differences over the step, so the GImpact peer is watched alike.
  Scene guarded = b.scene;
  if (guarded.guard.action == GuardAction::Stop) guarded.guard.action = GuardAction::Report;
  const RunawayGuard guard(guarded, c.kinetic());
  std::vector<GuardBodyState> states;
  for (const Rigid& pose : c.poses()) states.push_back({pose.translation(), Vec3::Zero()});
  bool runawaySeen = false;
  const int frames = std::max(1, int(std::lround(seconds / c.timestep)));
  const int probeEvery = std::max(1, int(std::lround(probeEverySeconds / c.timestep)));
  for (int f = 0; f < frames && run.why.empty(); ++f) {
    const double cpuStart = threadCpuSeconds();
    c.step();
    run.cpuSeconds += threadCpuSeconds() - cpuStart;
    run.frames = f + 1;
    if (c.nonFinite()) {
      run.why = "NaN";
      break;
    }
    const std::vector<Rigid> poses = c.poses();
    for (std::size_t i = 0; i < poses.size() && i < states.size(); ++i) {
      states[i].velocity = (poses[i].translation() - states[i].position) / c.timestep;
      states[i].position = poses[i].translation();
    }
    if (!runawaySeen) {
      if (const std::optional<std::string> runaway = guard.check((f + 1) * c.timestep, states, c.kinetic())) {
        // Reported once; a stability run (maxCells > 0) ends as unstable, a timing run goes on.
        std::printf("  %s: runaway: %s\n", c.name.c_str(), runaway->c_str());
        runawaySeen = true;
        if (maxCells > 0) {
          run.why = "runaway";
          break;
        }
      }
    }
    const double gain = totalEnergy(b, c) - start;
    run.energyGain = std::max(run.energyGain, gain);
    if (maxCells > 0 && gain > 0.05 * std::abs(start) + 0.5) run.why = "energy gain";
    if (f % probeEvery != 0 && f + 1 != frames) continue;
    const PenetrationSample p = b.probe->measure(c.poses());
    run.groundMetres = std::max(run.groundMetres, p.groundMetres);
    run.bodyMetres = std::max(run.bodyMetres, p.bodyMetres);
    if (maxCells > 0 && run.why.empty() && std::max(p.groundMetres, p.bodyMetres) > maxCells * cell) {
      run.why = "penetration";
    }
  }
  if (run.why != "NaN") run.tunneled = int(b.probe->tunneled(c.poses()).size());
  if (run.why.empty() && run.tunneled > 0) run.why = "tunnelled";
  return run;
}

void printTimingRow(const BenchScene& b, const Contender& c, const ContenderRun& r, const CsvSink& csv) {
  const double cell = b.probe->cellSize();
  const double simulated = r.frames * c.timestep;
  const double perStep = r.frames > 0 ? r.cpuSeconds / r.frames : 0.0;
  const double perSecond = simulated > 0 ? r.cpuSeconds / simulated : 0.0;
  std::printf("  %-34s %8.2f %6d %7.3f %9.2f %10.3f %7.2f %7.2f %4d %+9.2f\n", c.name.c_str(), 1e3 * c.timestep,
              r.frames, simulated, 1e3 * perStep, perSecond, r.groundMetres / cell, r.bodyMetres / cell, r.tunneled,
              r.energyGain);
  const std::string item = b.label + ":" + c.name;
  csv("modes", item, "timestep_s", c.timestep);
  csv("modes", item, "frames", r.frames);
  csv("modes", item, "step_cpu_seconds", r.cpuSeconds);
  csv("modes", item, "cpu_ms_per_step", 1e3 * perStep);
  csv("modes", item, "cpu_s_per_simulated_s", perSecond);
  csv("modes", item, "max_ground_penetration_cells", r.groundMetres / cell);
  csv("modes", item, "max_body_penetration_cells", r.bodyMetres / cell);
  csv("modes", item, "tunneled_bodies", r.tunneled);
  csv("modes", item, "max_energy_gain_j", r.energyGain);
  csv("modes", item, "nan", r.why == "NaN" ? 1 : 0);
}

void timeScene(const ModeBenchOptions& o, const BenchScene& b, bool withShipped, const CsvSink& csv) {
  const double seconds = o.quick ? std::min(o.timingSeconds, 0.3) : o.timingSeconds;
  const double gimpactSeconds = std::min(seconds, o.quick ? std::min(o.gimpactSeconds, 0.05) : o.gimpactSeconds);
  std::printf("\n%s: %zu bodies, %.2f s simulated (GImpact %.2f s), cell %.2f mm\n", b.label.c_str(),
              b.scene.bodies.size(), seconds, gimpactSeconds, 1e3 * b.probe->cellSize());
  std::printf("  %-34s %8s %6s %7s %9s %10s %7s %7s %4s %9s\n", "world", "dt (ms)", "frames", "sim s", "ms/step",
              "s/sim s", "ground", "body", "tun.", "dE max J");
  std::vector<std::pair<Contender, double>> contenders;
  contenders.emplace_back(
      oursContender(o, b, "penalty (defaults), SdfccdShape", SdfccdContactMode::Penalty, kPenaltyStep, false), seconds);
  if (withShipped) {
    contenders.emplace_back(
        oursContender(o, b, "penalty (as drop-bunnies ships)", SdfccdContactMode::Penalty, kPenaltyStep, true),
        seconds);
  }
  contenders.emplace_back(
      oursContender(o, b, "solver (defaults), SdfccdShape", SdfccdContactMode::Solver, kSolverStep, false), seconds);
  contenders.emplace_back(oursContender(o, b, "solver, sequential_impulse", SdfccdContactMode::Solver, kSolverStep,
                                        false, ContactSolver::SequentialImpulse),
                          seconds);
  contenders.emplace_back(peerContender(b, "Bullet btGImpactMeshShape", PeerShape::GImpact, kSolverStep),
                          gimpactSeconds);
  contenders.emplace_back(peerContender(b, "Bullet convex hull / btBoxShape", PeerShape::ConvexHull, kSolverStep),
                          seconds);
  for (auto& [c, s] : contenders) {
    std::fprintf(stderr, "  modes: %s, %s ...\n", b.label.c_str(), c.name.c_str());
    const ContenderRun r = runContender(b, c, s, 0.0, probeInterval(o));
    printTimingRow(b, c, r, csv);
    std::fflush(stdout);
  }
}

// The largest stable step of one mode: walks `steps` upwards, stops at the first unstable one.
void searchMode(const ModeBenchOptions& o, const BenchScene& b, const char* mode, const std::vector<double>& steps,
                double seconds, const CsvSink& csv) {
  double largest = 0.0;
  for (const double dt : steps) {
    Contender c = oursContender(
        o, b, mode, std::string(mode) == "penalty" ? SdfccdContactMode::Penalty : SdfccdContactMode::Solver, dt, false);
    std::fprintf(stderr, "  stable: %s, %s at %.3f ms ...\n", b.label.c_str(), mode, 1e3 * dt);
    const ContenderRun r = runContender(b, c, seconds, o.maxPenetrationCells, probeInterval(o));
    const double cell = b.probe->cellSize();
    std::printf(
        "  %-8s dt %7.3f ms (1/%-4.0f s): %-8s ground %5.2f, body %5.2f cells, dE max %+9.2f J, %4.1f ms CPU/step %s\n",
        mode, 1e3 * dt, 1.0 / dt, r.why.empty() ? "stable" : "UNSTABLE", r.groundMetres / cell, r.bodyMetres / cell,
        r.energyGain, r.frames > 0 ? 1e3 * r.cpuSeconds / r.frames : 0.0, r.why.c_str());
    const std::string item = b.label + ":" + mode + "@" + std::to_string(dt);
    csv("stable", item, "stable", r.why.empty() ? 1 : 0);
    csv("stable", item, "max_ground_penetration_cells", r.groundMetres / cell);
    csv("stable", item, "max_body_penetration_cells", r.bodyMetres / cell);
    csv("stable", item, "max_energy_gain_j", r.energyGain);
    std::fflush(stdout);
    if (!r.why.empty()) break;
    largest = dt;
  }
  std::printf("  largest stable step, %s: %s\n", mode,
              largest > 0 ? (std::to_string(1e3 * largest) + " ms").c_str() : "none of the steps tried");
  csv("stable", b.label + ":" + mode, "largest_stable_dt", largest);
}

}  // namespace

void runModeTiming(const ModeBenchOptions& o, const CsvSink& csv) {
  std::printf(
      "\nContact modes beside Bullet's own shapes (not in the paper). Thread CPU time of the steps, one "
      "thread; penetration in field cells of mesh vertices (the same probe for every world); tun.: tunnelled "
      "bodies at the end; dE max: largest rise of the total energy above the start. The paper has no such figure.\n");
  const BenchScene bunnies = loadBenchScene(o, "20 bunnies", "drop-bunnies.json");
  timeScene(o, bunnies, true, csv);
  const BenchScene stack = loadBenchScene(o, "10-box stack", "stack-boxes.json");
  timeScene(o, stack, false, csv);
}

void runModeStability(const ModeBenchOptions& o, const CsvSink& csv) {
  const std::vector<double> penaltySteps = {0.001, 0.0015, 0.002, 0.003, 0.004};
  const std::vector<double> solverSteps = {1.0 / 960, 1.0 / 480, 1.0 / 240, 1.0 / 120, 1.0 / 60};
  const double seconds = o.quick ? 0.3 : 1.0;
  std::printf("\nLargest stable step of each contact mode (project defaults, %.1f s simulated per trial). ", seconds);
  std::printf(kModeStabilityCriterion, o.maxPenetrationCells, 1e3 * probeInterval(o));
  std::printf(".\n");
  for (const auto& [label, file] :
       {std::pair<const char*, const char*>{"20 bunnies", "drop-bunnies.json"}, {"10-box stack", "stack-boxes.json"}}) {
    const BenchScene b = loadBenchScene(o, label, file);
    std::printf("%s:\n", label);
    searchMode(o, b, "penalty", o.quick ? std::vector<double>{0.001, 0.002, 0.004} : penaltySteps, seconds, csv);
    searchMode(o, b, "solver", o.quick ? std::vector<double>{1.0 / 240, 1.0 / 60} : solverSteps, seconds, csv);
  }
}

}  // namespace sdfccd::cli

#endif
