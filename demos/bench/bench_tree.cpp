/// @file
/// @brief `sdfccd bench tree [--quick] [--out CSV]`: the paper's Table 3 (Section 3.3): rigid CCD of a point
/// shell against a field, point by point ("linear") vs the nested point tree.
///
/// @details Protocol of the paper: 1,000 random pairs of poses (position uniform in the field's box expanded
/// 3x about its centre, orientation uniform) for the shell, CCD of every point's segment against the zero level
/// set of the field. Models: the bunny (777 points sampled on assets/meshes/bunny.off), a lathed china bowl
/// (2,072 points; a procedural stand-in for the paper's scanned bowl) and the dragon (437,645 points sampled
/// on assets/meshes/dragon.off; sampled once and cached in the model cache folder, --cache). Each shell's frame is
/// centred on its mesh's box, each field is the SDF of the same mesh (buildSdf), so the shell overlaps its own model's
/// field. Single thread, exact roots, full octree, first hit at the leaves (CCD: the time of contact;
/// --mode all-intervals for the penalty integrals' intervals) for both traversals; the tree's contacts are
/// checked equal to the linear ones. The output also times the queries of the touching points alone: no
/// hierarchy can do less, so linear / that time bounds the possible speedup of the protocol.
/// --query earliest: only the body's earliest contact (time of impact; RigidCcdSettings::earliestOnly, branch
/// and bound in the tree) for both traversals, checked equal; earliest-one: the same with one witness point
/// (earliestOneContact: what a time-of-impact solver needs); the default (all) returns every contact.
/// The paper used 1024^3 fields; we state ours (--resolution). --quick: 64^3 fields, 100 configurations and
/// a 20,000-point dragon, in seconds.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench/cache_option.h"
#include "bench/option_checks.h"
#include "bench/random_pose.h"
#include "cli/bench_registry.h"
#include "cli/progress_bar.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/error.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/io/mesh_loader.h"
#include "sdfccd/mesh/procedural_meshes.h"
#include "sdfccd/mesh/sdf_builder.h"
#include "sdfccd/output_file.h"
#include "sdfccd/shell/point_shell.h"
#include "sdfccd/shell/point_tree.h"
#include "sdfccd/thread_cpu_time.h"

#ifndef SDFCCD_ASSETS_DIR_CLI
#define SDFCCD_ASSETS_DIR_CLI "assets"
#endif

namespace sdfccd::cli {
namespace {

struct BenchTreeOptions {
  bool quick = false;
  std::string csv = "bench_tree.csv";
  std::string assets = SDFCCD_ASSETS_DIR_CLI;
  std::string cache;   // resolved by resolveCacheOption before the run
  int resolution = 0;  // 0: 256 (full) or 64 (quick)
  int configs = 0;     // 0: 1000 (full) or 100 (quick)
  int dragonPoints = 0;
  std::string models = "bunny,bowl,dragon";
  std::uint32_t seed = 2024;
  std::string mode = "first-hit";
  std::string motion = "random";
  std::string query = "both";
  double cullLipschitz = 0.0;
  int branching = PointTreeSettings{}.branching;
};

struct Model {
  std::string name;
  int points;
  double paperLinear;  // s, 1024^3 fields, 1,000 configurations
  double paperTree;    // s
};

using Clock = std::chrono::steady_clock;
double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

using bench::randomPose;

// The shell of a model: sampled by repulsion, from the cache when there.
PointShell modelShell(const std::string& name, const TriangleMesh& mesh, int points, const std::string& cacheDir,
                      bool useCache) {
  useCache = useCache && !cacheDir.empty();  // --cache "": no cache
  const std::string cachePath = cacheDir + "/" + name + "_" + std::to_string(points) + ".ply";
  if (useCache && std::filesystem::exists(cachePath)) {
    PointShell shell = loadShell(cachePath);
    if (static_cast<int>(shell.size()) == points) {
      std::printf("  %s shell: %d points from the cache %s\n", name.c_str(), points, cachePath.c_str());
      return shell;
    }
  }
  ShellSamplingSettings settings;
  settings.points = points;
  settings.threads = 0;
  const auto start = Clock::now();
  PointShell shell;
  {
    ProgressBar bar("sampling the " + name + " shell");
    settings.progress = bar.callback();
    shell = sampleShell(mesh, settings);
  }
  std::printf("  %s shell: %d points sampled by repulsion in %.1f s\n", name.c_str(), points, since(start));
  std::fflush(stdout);
  if (useCache) {
    std::filesystem::create_directories(cacheDir);
    saveShell(shell, cachePath);
  }
  return shell;
}

struct Row {
  std::string model;
  std::string query;  // all, earliest, earliest-one
  int points = 0;
  double linear = 0.0;     // s: point by point, each point queried on its own (the paper's baseline)
  double linearCut = 0.0;  // s: earliest queries only: point by point, each cut at the best contact so far
  double tree = 0.0;       // s
  double paperLinear = 0.0;
  double paperTree = 0.0;
  double contactsPerConfig = 0.0;
  double hitConfigs = 0.0;
  double treeQueriesPerConfig = 0.0;
  std::string field;
  double contactSeconds = 0.0;
};

// One query kind over every configuration: linear, (cut linear,) tree, then the touching points alone,
// interleaved per configuration so that a change of the machine's load affects all alike; timed in CPU time of
// this thread (the machine may be shared). The tree's answer is checked against the linear one.
Row measureQuery(const std::string& query, const Model& m, const PointTree& tree, const GridField& field,
                 const std::vector<Rigid>& starts, const std::vector<Rigid>& ends, CcdMode leafMode,
                 double cullLipschitz) {
  const bool earliest = query != "all";
  const int configs = static_cast<int>(starts.size());
  RigidCcdSettings settings;
  settings.mode = leafMode;
  settings.earliestOnly = earliest;
  settings.earliestOneContact = query == "earliest-one";
  settings.cullLipschitz = cullLipschitz;
  // The paper's point-by-point baseline: every point's own CCD with the leaves' settings; for the earliest
  // query, the minimum over them.
  RigidCcdSettings independent = settings;
  independent.earliestOnly = false;
  independent.useTree = false;
  RigidCcdResult linear;
  RigidCcdResult cut;
  RigidCcdResult treeResult;
  SegmentCcdSettings leafSettings;
  leafSettings.mode = leafMode;
  SegmentCcdResult segment;
  Row row;
  row.model = m.name;
  row.query = query;
  row.points = tree.pointCount();
  row.paperLinear = m.paperLinear;
  row.paperTree = m.paperTree;
  std::int64_t queries = 0;
  std::int64_t contacts = 0;
  int hitConfigs = 0;
  // Split by configurations with and without contact: where each traversal spends its time.
  double linearHitSeconds = 0.0;
  double treeHitSeconds = 0.0;
  std::int64_t missQueries = 0;
  int wrongConfigs = 0;
  for (int c = 0; c < configs; ++c) {
    double t = threadCpuSeconds();
    rigidCcd(tree, field, starts[c], ends[c], independent, linear);
    const double linearOne = threadCpuSeconds() - t;
    row.linear += linearOne;
    if (earliest) {
      settings.useTree = false;
      t = threadCpuSeconds();
      rigidCcd(tree, field, starts[c], ends[c], settings, cut);
      row.linearCut += threadCpuSeconds() - t;
    }
    settings.useTree = true;
    t = threadCpuSeconds();
    rigidCcd(tree, field, starts[c], ends[c], settings, treeResult);
    const double treeOne = threadCpuSeconds() - t;
    row.tree += treeOne;
    if (!linear.contacts.empty()) {
      linearHitSeconds += linearOne;
      treeHitSeconds += treeOne;
    } else {
      missQueries += treeResult.stats.segmentQueries;
    }
    t = threadCpuSeconds();
    for (const auto& contact : earliest ? treeResult.contacts : linear.contacts) {
      const Vec3& x = tree.shell().positions[contact.point];
      field.intersectSegment(starts[c] * x, ends[c] * x, leafSettings, segment);
    }
    row.contactSeconds += threadCpuSeconds() - t;
    // earliest-one: each holds one witness, possibly different points tied at the same fraction.
    const bool agree =
        earliest ? (treeResult.firstFraction == linear.firstFraction && cut.firstFraction == linear.firstFraction &&
                    treeResult.contacts.empty() == linear.contacts.empty())
                 : (treeResult.contacts.size() == linear.contacts.size() &&
                    treeResult.firstFraction == linear.firstFraction);
    if (!agree) {
      if (cullLipschitz > 0.0) {  // a chosen bound may be too small: count what it misses
        ++wrongConfigs;
        continue;
      }
      throw Error("bench tree: the tree and the linear traversal disagree on " + m.name + ", configuration " +
                  std::to_string(c));
    }
    queries += treeResult.stats.segmentQueries;
    contacts += static_cast<std::int64_t>(treeResult.contacts.size());
    hitConfigs += treeResult.contacts.empty() ? 0 : 1;
  }
  row.contactsPerConfig = static_cast<double>(contacts) / configs;
  row.hitConfigs = static_cast<double>(hitConfigs) / configs;
  row.treeQueriesPerConfig = static_cast<double>(queries) / configs;
  std::printf("  %s, %s: linear %.3f s, tree %.3f s, speedup %.1fx", m.name.c_str(), query.c_str(), row.linear,
              row.tree, row.linear / row.tree);
  if (earliest) std::printf("; linear cut at the best contact %.3f s (%.1fx)", row.linearCut, row.linearCut / row.tree);
  std::printf("\n");
  std::printf(
      "  %s, %s: configurations with contact: linear %.3f s, tree %.3f s; without: linear %.3f s, tree %.3f s "
      "(%.1f tree queries each)\n",
      m.name.c_str(), query.c_str(), linearHitSeconds, treeHitSeconds, row.linear - linearHitSeconds,
      row.tree - treeHitSeconds,
      hitConfigs < configs ? static_cast<double>(missQueries) / (configs - hitConfigs) : 0.0);
  if (cullLipschitz > 0.0) {
    std::printf(
        "  %s, %s: node test with gradient bound %.2f: %d of %d configurations got answers different "
        "from the linear query's\n",
        m.name.c_str(), query.c_str(), cullLipschitz, wrongConfigs, configs);
  }
  std::fflush(stdout);
  return row;
}

int runBenchTree(const BenchTreeOptions& o) {
  const int resolution = o.resolution > 0 ? o.resolution : (o.quick ? 64 : 256);
  const int configs = o.configs > 0 ? o.configs : (o.quick ? 100 : 1000);
  const int dragonPoints = o.dragonPoints > 0 ? o.dragonPoints : (o.quick ? 20000 : 437645);
  if (o.motion != "random" && o.motion != "step") throw Error("--motion must be random or step");
  if (o.mode != "all-intervals" && o.mode != "first-hit") throw Error("--mode must be all-intervals or first-hit");
  const CcdMode leafMode = o.mode == "first-hit" ? CcdMode::FirstHit : CcdMode::AllIntervals;
  std::vector<std::string> queries;
  if (o.query == "both") {
    queries = {"all", "earliest-one"};
  } else if (o.query == "all" || o.query == "earliest" || o.query == "earliest-one") {
    queries = {o.query};
  } else {
    throw Error("--query must be all, earliest, earliest-one or both");
  }
  if (resolution < 8 || resolution > 2048) throw Error("--resolution must be in 8..2048");
  if (!(o.cullLipschitz >= 0.0) || o.cullLipschitz > 100.0) throw Error("--cull-lipschitz must be in [0, 100]");
  if (configs > 1000000) throw Error("--configs must be at most 1000000");
  if (dragonPoints > 5000000) throw Error("--dragon-points must be at most 5000000");
  std::vector<Model> models = {
      {"bunny", 777, 1.8, 0.7}, {"bowl", 2072, 3.4, 0.3}, {"dragon", dragonPoints, 761.2, 9.9}};
  std::vector<Model> chosen;
  for (const auto& m : models) {
    if (("," + o.models + ",").find("," + m.name + ",") != std::string::npos) chosen.push_back(m);
  }
  if (chosen.empty()) throw Error("--models: none of bunny, bowl, dragon");

  std::printf("Table 3: rigid CCD of point shells vs their SDFs, linear (point by point) vs point tree\n");
  std::printf("machine: %s; 1 thread, CPU time of the querying thread\n", machineDescription().c_str());
  std::printf(
      "protocol: %d random pose pairs in the 3x expanded field box (motion: %s), zero level set, exact "
      "roots, %s at the leaves; fields %d cells along the longest side plus a margin of 4/256 of it (paper: 1024^3)\n",
      configs, o.motion == "random" ? "independent start and end poses" : "short steps, NOT Table 3", o.mode.c_str(),
      resolution);
  std::printf(
      "queries: all = every contact; earliest = the time of impact and every point tied at it; earliest-one = "
      "the time of impact and one witness (tree: best-first branch and bound). linear = every point's own "
      "query (the paper's point-by-point baseline); lin. cut = point by point, each point cut at the best "
      "contact so far (a stronger baseline of ours)\n");
  if (o.quick) {
    std::printf(
        "QUICK RUN: %d^3-class fields, %d configurations, a %d-point dragon (paper: 437,645) -- not the "
        "paper's protocol; run without --quick for Table 3\n",
        resolution, configs, dragonPoints);
  }
  std::fflush(stdout);

  std::vector<Row> rows;
  for (const Model& m : chosen) {
    TriangleMesh mesh;
    if (m.name == "bowl") {
      mesh = makeLathedBowl();
    } else {
      mesh = loadMesh(o.assets + "/meshes/" + m.name + ".off");
    }
    SdfBuildSettings build;
    build.resolution = resolution;
    // The same margin around the model at every resolution (4 cells at 256^3), so the field's box, and with it
    // the 3x box the poses are drawn from, does not change with the resolution.
    build.padding = std::max(1, (4 * resolution + 128) / 256);
    build.threads = 0;
    auto start = Clock::now();
    SdfBuildResult sdf;
    {
      ProgressBar bar("building the " + m.name + " SDF");
      build.progress = bar.callback();
      sdf = buildSdf(mesh, build);
    }
    const GridField field(sdf.grid);
    const Vec3i nodes = sdf.grid->nodeCounts();
    char fieldText[96];
    std::snprintf(fieldText, sizeof fieldText, "%dx%dx%d", nodes.x(), nodes.y(), nodes.z());
    std::printf("  %s field: %s nodes, built in %.1f s\n", m.name.c_str(), fieldText, since(start));
    std::fflush(stdout);

    PointShell shell = modelShell(m.name, mesh, m.points, o.cache, m.name == "dragon" && !o.quick);
    const Vec3 centre = mesh.bounds().center();
    for (auto& p : shell.positions) p -= centre;  // the body frame: centred on the model's box
    start = Clock::now();
    PointTreeSettings treeSettings;
    treeSettings.branching = o.branching;
    const PointTree tree(std::move(shell), treeSettings);
    std::printf("  %s tree: %d nodes, %d levels, built in %.3f s\n", m.name.c_str(), tree.nodeCount(),
                tree.levelCount(), since(start));

    // The poses (drawn before timing), shared by both traversals.
    Box3 box = sdf.grid->box();
    const Vec3 half = 1.5 * box.sizes();
    box = Box3(box.center() - half, box.center() + half);
    std::mt19937 rng(o.seed);
    std::vector<Rigid> starts(configs);
    std::vector<Rigid> ends(configs);
    const double step = 0.05 * sdf.grid->box().sizes().norm();
    std::normal_distribution<double> gauss(0.0, 1.0);
    for (int c = 0; c < configs; ++c) {
      starts[c] = randomPose(box, rng);
      if (o.motion == "random") {
        ends[c] = randomPose(box, rng);
      } else {  // one simulation-like step: 5% of the box diagonal, 0.1 rad
        const Vec3 axis = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
        const Vec3 move = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized() * step;
        ends[c] = starts[c];
        ends[c].linear() = Eigen::AngleAxisd(0.1, axis).toRotationMatrix() * starts[c].linear();
        ends[c].translation() += move;
      }
    }
    for (const std::string& query : queries) {
      rows.push_back(measureQuery(query, m, tree, field, starts, ends, leafMode, o.cullLipschitz));
      rows.back().field = fieldText;
    }
    std::printf("  %s: field Lipschitz bound %.2f\n", m.name.c_str(), fieldCullingBounds(field).lipschitz);
    std::fflush(stdout);
  }

  std::printf("\n%-8s %-12s %9s %8s %14s %10s %10s %10s %8s %8s | %10s %10s %8s | %8s %9s %9s\n", "model", "query",
              "points", "configs", "field", "linear [s]", "lin. cut", "tree [s]", "speedup", "vs cut", "paper lin.",
              "paper tree", "paper x", "hit cfgs", "contacts", "queries");
  for (const Row& r : rows) {
    const bool cut = r.query != "all";
    char cutText[32] = "-";
    char cutSpeedup[32] = "-";
    if (cut) {
      std::snprintf(cutText, sizeof cutText, "%.3f", r.linearCut);
      std::snprintf(cutSpeedup, sizeof cutSpeedup, "%.1fx", r.linearCut / r.tree);
    }
    std::printf("%-8s %-12s %9d %8d %14s %10.3f %10s %10.3f %7.1fx %8s | %10.1f %10.1f %7.1fx | %7.0f%% %9.1f %9.1f\n",
                r.model.c_str(), r.query.c_str(), r.points, configs, r.field.c_str(), r.linear, cutText, r.tree,
                r.linear / r.tree, cutSpeedup, r.paperLinear, r.paperTree, r.paperLinear / r.paperTree,
                100.0 * r.hitConfigs, r.contactsPerConfig, r.treeQueriesPerConfig);
  }
  std::printf(
      "(paper: 1024^3 fields, 1,000 configurations, seconds for all of them. contacts, queries: the tree's, per "
      "configuration. all: every point touching must be queried whatever the traversal, which bounds the "
      "speedup of any hierarchy by linear / (those queries alone):");
  for (const Row& r : rows) {
    if (r.query == "all") std::printf(" %s %.1fx", r.model.c_str(), r.linear / r.contactSeconds);
  }
  std::printf(")\n");
  if (!o.csv.empty()) {
    OutputFile file(o.csv);
    file.stream() << "model,points,configs,linear_s,tree_s,speedup,query,linear_cut_s,paper_linear_s,paper_tree_s\n";
    for (const Row& r : rows) {
      file.stream() << r.model << ',' << r.points << ',' << configs << ',' << r.linear << ',' << r.tree << ','
                    << r.linear / r.tree << ',' << r.query << ',' << (r.query == "all" ? 0.0 : r.linearCut) << ','
                    << r.paperLinear << ',' << r.paperTree << '\n';
    }
    file.commit();
    std::printf("csv: %s\n", o.csv.c_str());
  }
  return 0;
}

const BenchRegistrar bench_treeRegistrar(
    "tree", "Table 3: rigid CCD, point by point vs the point tree", [](CLI::App& cmd) {
      auto o = std::make_shared<BenchTreeOptions>();
      cmd.add_flag("--quick", o->quick, "Seconds-long run: 64^3 fields, 100 configurations, a 20,000-point dragon");
      cmd.add_option("--out", o->csv, "CSV output (model,points,configs,linear_s,tree_s,speedup); empty: none");
      cmd.add_option("--assets", o->assets, "The assets folder (meshes/bunny.off, meshes/dragon.off)");
      const CLI::Option* cache = addCacheOption(cmd, o->cache, "Where the dragon shell is cached");
      cmd.add_option("--resolution", o->resolution,
                     "Cells along the longest side of each field (default 256; quick 64)")
          ->check(countIn(8, 4096));
      cmd.add_option("--configs", o->configs, "Random pose pairs per model (default 1000; quick 100)")
          ->check(countIn(1, 10000000));
      cmd.add_option("--dragon-points", o->dragonPoints, "Points of the dragon shell (default 437645; quick 20000)")
          ->check(countIn(1, 10000000));
      cmd.add_option("--models", o->models, "Comma-separated subset of bunny,bowl,dragon")->check(nonEmpty());
      cmd.add_option("--seed", o->seed, "Seed of the poses");
      cmd.add_option("--mode", o->mode,
                     "What the leaves compute: first-hit (default: CCD = time of contact) or all-intervals");
      cmd.add_option("--motion", o->motion,
                     "random: independent start and end poses (Table 3, default); step: a short "
                     "simulation-like step from each random pose");
      cmd.add_option("--query", o->query,
                     "all: every contact; earliest: only the earliest contact (time of impact, branch and "
                     "bound) and every point tied at it; earliest-one: the earliest contact and one witness point; "
                     "both (default): all, then earliest-one");
      cmd.add_option("--branching", o->branching, "Children per inner node of the point tree (default 8)");
      cmd.add_option("--cull-lipschitz", o->cullLipschitz,
                     "Gradient bound of the node test (default 0: the field's own bound, which never misses a "
                     "contact; 1: the paper's test, which can miss contacts of a steep grid)");
      return std::function<int()>([o, cache]() {
        o->cache = resolveCacheOption(cache, o->cache);
        return runBenchTree(*o);
      });
    });

}  // namespace
}  // namespace sdfccd::cli
