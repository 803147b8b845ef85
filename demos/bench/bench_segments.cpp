/// @file
/// @brief `sdfccd bench segments [--quick] [--out CSV] [--field PATH]`: the segment CCD's speed and accuracy
/// (paper Table 2, Sections 3.1-3.2).
///
/// @details Three protocols, one core, first-hit mode, sigma = 0:
/// 1. Table 2: segments between uniformly random points in the bunny field's box at 128^3, 256^3, 512^3;
///    uniform walk (octree off) vs octree (leaves, full), exact vs bisection. Paper, s per 10^6 segments:
///    uniform 12.7 / 38.8 / 97.2, octree 12.0 / 13.1 / 15.4 (2015 Xeon).
/// 2. Haptic rate: segments of at most 2 cells starting near the surface (0 < phi < 2 cells); leaves vs full
///    vs off (paper: leaves 1.5x faster than off, full 2-3x slower than leaves at these lengths).
/// 3. Exact vs bisection: the time ratio (paper: bisection 1.2x faster) and how many first hits bisection
///    misses (exact hits, bisection does not) or misplaces (both hit, > 1% of a cell apart), on the bunny
///    sets and on a random field (independent random node values: several roots per cell).
/// Bunny fields are built with buildSdf from assets/meshes/bunny.off (padding 0, as the paper's grids) and
/// cached in the model cache folder (--cache; native format) so later runs only load them.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench/cache_option.h"
#include "bench/openvdb_peer.h"
#include "bench/option_checks.h"
#include "bench/segment_experiments.h"
#include "cli/bench_registry.h"
#include "sdfccd/error.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/field/sdf_file.h"

#ifndef SDFCCD_ASSETS_DIR_CLI
#define SDFCCD_ASSETS_DIR_CLI "assets"
#endif

namespace sdfccd::cli {
namespace {

struct BenchSegmentsOptions {
  bool quick = false;
  std::string csv = "bench_segments.csv";
  std::string field;
  std::string mesh;
  std::string cache;       // resolved by resolveCacheOption before the run
  long long segments = 0;  // 0: 10^6 (10^5 with --quick)
  std::string method;      // only this method (empty: both)
  std::string octree;      // only this octree mode (empty: all)
  unsigned seed = 1;
};

struct PaperTable2 {
  int resolution;
  double uniform, octree;  // s per 10^6 segments
};

int runBenchSegments(const BenchSegmentsOptions& o) {
  const long long count = o.segments > 0 ? o.segments : (o.quick ? 100000 : 1000000);
  if (count > 100000000) throw Error("--segments must be at most 1e8");
  std::vector<PaperTable2> rows = {{128, 12.7, 12.0}, {256, 38.8, 13.1}, {512, 97.2, 15.4}};
  if (o.quick) rows = {{64, 0.0, 0.0}, {128, 12.7, 12.0}};
  if (!o.field.empty()) rows = {{0, 0.0, 0.0}};

  std::printf("Segment CCD benchmark (paper Table 2 and Sections 3.1-3.2); one core, first hit, sigma = 0\n");
  std::printf("machine: %s (paper: 2015 Xeon)\n", machineDescription().c_str());
  std::ofstream csv;
  if (!o.csv.empty()) {
    csv.open(o.csv);
    if (!csv) throw Error("cannot write '" + o.csv + "'");
    csv << "protocol,field,cells,method,octree,segments,us_per_segment_cpu,us_per_segment_wall,paper_s_per_1e6,hits,"
           "octree_memory_ratio,machine\n";
  }
  auto csvRow = [&](const char* protocol, const std::string& field, int cells, const char* method, const char* octree,
                    std::size_t n, const SegmentTiming& r, double paper, double ratio) {
    if (!csv) return;
    csv << protocol << ',' << field << ',' << cells << ',' << method << ',' << octree << ',' << n << ','
        << r.microseconds << ',' << r.wallMicroseconds << ',' << paper << ',' << r.hits << ',' << ratio << ",\""
        << machineDescription() << "\"\n";
  };

  struct Config {
    CcdMethod method;
    OctreeMode octree;
    const char* methodName;
    const char* octreeName;
  };
  const std::vector<Config> configs = {
      {CcdMethod::Exact, OctreeMode::Off, "exact", "off"},
      {CcdMethod::Exact, OctreeMode::Leaves, "exact", "leaves"},
      {CcdMethod::Exact, OctreeMode::Full, "exact", "full"},
      {CcdMethod::Bisection, OctreeMode::Off, "bisection", "off"},
      {CcdMethod::Bisection, OctreeMode::Leaves, "bisection", "leaves"},
      {CcdMethod::Bisection, OctreeMode::Full, "bisection", "full"},
  };

  auto selected = [&](const Config& c) {
    return (o.method.empty() || o.method == c.methodName) && (o.octree.empty() || o.octree == c.octreeName);
  };
  const bool everything = o.method.empty() && o.octree.empty();
  std::printf("times: thread CPU time per segment (us = s per 10^6 segments); wall time in the CSV\n");
  std::printf("\n%-22s %7s %-10s %-7s %9s %12s %12s %12s %9s\n", "protocol", "cells", "method", "octree", "segments",
              "us/segment", "wall us/seg", "paper s/1e6", "hits");
  for (const PaperTable2& row : rows) {
    const std::string meshPath = o.mesh.empty() ? std::string(SDFCCD_ASSETS_DIR_CLI) + "/meshes/bunny.off" : o.mesh;
    const auto grid = o.field.empty() ? cachedBunnyField(o.cache, meshPath, row.resolution, 0, stdout)
                                      : std::make_shared<const SdfGrid>(loadSdf(o.field));
    const std::string fieldName = o.field.empty() ? "bunny" : o.field;
    const auto buildStart = std::chrono::steady_clock::now();
    const GridField field(grid);
    const double buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - buildStart).count();
    const int cells = grid->cellCounts().maxCoeff();
    const double ratio = static_cast<double>(field.octree().memoryBytes()) / static_cast<double>(grid->memoryBytes());
    std::printf(
        "-- %s %dx%dx%d cells: octree %.1f MB = %.1f%% of the grid's %.1f MB (paper: ~2x the grid), built in %.3f s\n",
        fieldName.c_str(), grid->cellCounts().x(), grid->cellCounts().y(), grid->cellCounts().z(),
        field.octree().memoryBytes() / 1e6, 100.0 * ratio, grid->memoryBytes() / 1e6, buildSeconds);

    // Protocol 1: Table 2.
    const std::vector<Segment> random = randomSegmentsInBox(grid->box(), static_cast<std::size_t>(count), o.seed);
    // The uniform walk is slow at high resolution: time it on at most 2e5 segments (us per segment is what counts).
    const std::size_t uniformCount = std::min<std::size_t>(random.size(), 200000);
    double exactFull = 0.0, bisectionFull = 0.0;
    for (const Config& c : configs) {
      if (!selected(c)) continue;
      const std::size_t n = c.octree == OctreeMode::Off ? uniformCount : random.size();
      const SegmentTiming r = timeSegmentQueries(field, random, c.method, c.octree, n, false);
      double paper = 0.0;
      if (c.method == CcdMethod::Exact && c.octree == OctreeMode::Off) paper = row.uniform;
      if (c.method == CcdMethod::Exact && c.octree == OctreeMode::Full) paper = row.octree;
      if (c.octree == OctreeMode::Full) (c.method == CcdMethod::Exact ? exactFull : bisectionFull) = r.microseconds;
      char paperText[32] = "-";
      if (paper > 0.0) std::snprintf(paperText, sizeof(paperText), "%.1f", paper);
      std::printf("%-22s %7d %-10s %-7s %9zu %12.3f %12.2f %12s %9lld\n", "table2-random", cells, c.methodName,
                  c.octreeName, n, r.microseconds, r.wallMicroseconds, paperText, r.hits);
      csvRow("table2-random", fieldName, cells, c.methodName, c.octreeName, n, r, paper, ratio);
    }
    if (everything)
      std::printf("   exact/bisection time ratio (full octree): %.2f (paper: 1.2)\n", exactFull / bisectionFull);

#ifdef SDFCCD_HAS_OPENVDB
    // The peer: OpenVDB's LevelSetRayIntersector on the same segments (those starting outside the surface:
    // a ray intersector reports crossings, not "starts inside").
    if (everything) {
      std::vector<PeerSegment> peerSegments;
      SegmentCcdSettings exact;
      exact.mode = CcdMode::FirstHit;
      SegmentCcdResult r;
      for (const Segment& seg : random) {
        if (peerSegments.size() >= 200000) break;
        if (!(field.distance(seg.p0) > 0.0)) continue;
        field.intersectSegment(seg.p0, seg.p1, exact, r);
        peerSegments.push_back({seg.p0, seg.p1, r.hit() ? r.fraction : -1.0});
      }
      const OpenVdbPeerResult peer = runOpenVdbPeer(*grid, peerSegments);
      std::printf("%-22s %7d %-10s %-7s %9lld %12.3f %12s %12s %9lld\n", "openvdb-peer", cells, "vdb-ray", "-",
                  peer.segments, peer.microseconds, "-", "-", peer.peerHits);
      std::printf(
          "   OpenVDB LevelSetRayIntersector (narrow band 3 cells, %.1f MB, converted in %.2f s) vs our exact: "
          "%lld our hits, %lld missed, %lld misplaced (>1%% cell), %lld spurious; mean |phi| at the hits: "
          "OpenVDB %.2e, ours %.2e cells\n",
          peer.vdbBytes / 1e6, peer.conversionSeconds, peer.exactHits, peer.missed, peer.misplaced, peer.spurious,
          peer.meanAbsPhiPeer, peer.meanAbsPhiOurs);
      if (csv) {
        csv << "openvdb-peer," << fieldName << ',' << cells << ",vdb-ray,-," << peer.segments << ','
            << peer.microseconds << ",,," << peer.peerHits << ',' << ratio << ",\"" << machineDescription() << "\"\n";
        csv << "misses-openvdb," << fieldName << ',' << cells << ",vdb-ray,-," << peer.exactHits << ",,,,"
            << peer.missed << ';' << peer.misplaced << ';' << peer.spurious << ',' << ratio << ",\""
            << machineDescription() << "\"\n";
      }
    }
#endif

    // Protocol 2: haptic rate.
    const std::vector<Segment> haptic = hapticSegments(field, static_cast<std::size_t>(count), o.seed + 1);
    double hapticTimes[3] = {0, 0, 0};
    for (const Config& c : configs) {
      if (!selected(c)) continue;
      const SegmentTiming r = timeSegmentQueries(field, haptic, c.method, c.octree, haptic.size(), false);
      if (c.method == CcdMethod::Exact) hapticTimes[static_cast<int>(c.octree)] = r.microseconds;
      std::printf("%-22s %7d %-10s %-7s %9zu %12.3f %12.2f %12s %9lld\n", "haptic-short", cells, c.methodName,
                  c.octreeName, haptic.size(), r.microseconds, r.wallMicroseconds, "-", r.hits);
      csvRow("haptic-short", fieldName, cells, c.methodName, c.octreeName, haptic.size(), r, 0.0, ratio);
    }
    const double off = hapticTimes[static_cast<int>(OctreeMode::Off)];
    const double leaves = hapticTimes[static_cast<int>(OctreeMode::Leaves)];
    const double full = hapticTimes[static_cast<int>(OctreeMode::Full)];
    if (everything)
      std::printf("   haptic, exact: off/leaves = %.2f (paper: 1.5), full/leaves = %.2f (paper: 2-3)\n", off / leaves,
                  full / leaves);

    // Protocol 3: bisection's misses on this field.
    if (!everything) continue;
    const BisectionVsExact mr = compareBisectionToExact(field, random, std::min<std::size_t>(random.size(), 200000));
    const BisectionVsExact mh = compareBisectionToExact(field, haptic, haptic.size());
    std::printf(
        "   bisection vs exact, random: %lld exact hits, %lld missed, %lld misplaced (>1%% cell), %lld spurious\n",
        mr.exactHits, mr.missed, mr.misplaced, mr.spurious);
    std::printf(
        "   bisection vs exact, haptic: %lld exact hits, %lld missed, %lld misplaced (>1%% cell), %lld spurious\n",
        mh.exactHits, mh.missed, mh.misplaced, mh.spurious);
    if (csv) {
      for (const auto& [name, m] :
           {std::pair<const char*, BisectionVsExact>{"misses-random", mr}, {"misses-haptic", mh}}) {
        csv << name << ',' << fieldName << ',' << cells << ",bisection,full," << m.exactHits << ",,,," << m.missed
            << ';' << m.misplaced << ';' << m.spurious << ',' << ratio << ",\"" << machineDescription() << "\"\n";
      }
    }
    std::fflush(stdout);
  }

  // Protocol 3 on a random field: independent node values in [-1, 1], several roots per cell.
  if (everything) {
    const GridField field(randomValueGrid(32, o.seed));
    // Segments of up to 2 cells (long ones almost always start near a crossing cell).
    const std::vector<Segment> segments = shortRandomSegments(field.grid().box(), 2.0, 100000, o.seed + 2);
    const BisectionVsExact m = compareBisectionToExact(field, segments, segments.size());
    const SegmentTiming e =
        timeSegmentQueries(field, segments, CcdMethod::Exact, OctreeMode::Full, segments.size(), false);
    const SegmentTiming b =
        timeSegmentQueries(field, segments, CcdMethod::Bisection, OctreeMode::Full, segments.size(), false);
    std::printf("-- random field 32^3 cells, values in [-1,1], 1e5 segments of <= 2 cells\n");
    std::printf(
        "   bisection vs exact: %lld exact hits, %lld missed (%.2f%%), %lld misplaced (%.2f%%), %lld spurious\n",
        m.exactHits, m.missed, 100.0 * m.missed / std::max<long long>(m.exactHits, 1), m.misplaced,
        100.0 * m.misplaced / std::max<long long>(m.exactHits, 1), m.spurious);
    std::printf("   time: exact %.3f us, bisection %.3f us, ratio %.2f (paper: 1.2)\n", e.microseconds, b.microseconds,
                e.microseconds / b.microseconds);
    if (csv) {
      csv << "misses-random-field,random,32,bisection,full," << m.exactHits << ",,,," << m.missed << ';' << m.misplaced
          << ';' << m.spurious << ",,\"" << machineDescription() << "\"\n";
    }
  }
  if (!o.csv.empty()) std::printf("wrote %s\n", o.csv.c_str());
  return 0;
}

const BenchRegistrar bench_segmentsRegistrar(
    "segments", "Table 2: segment CCD, uniform walk vs octree, exact vs bisection", [](CLI::App& sub) {
      auto o = std::make_shared<BenchSegmentsOptions>();
      sub.add_flag("--quick", o->quick, "64^3 and 128^3, 1e5 segments (seconds)");
      sub.add_option("--out", o->csv, "CSV output (default bench_segments.csv; empty: none)");
      sub.add_option("--field", o->field, "Use this field file instead of the bunny builds")->check(nonEmpty());
      sub.add_option("--mesh", o->mesh, "Mesh for the bunny builds (default assets/meshes/bunny.off)")
          ->check(nonEmpty());
      const CLI::Option* cache = addCacheOption(sub, o->cache, "Folder of cached bunny fields");
      sub.add_option("--segments", o->segments, "Segments per protocol (default 1e6; 1e5 quick)")
          ->check(countIn(1, 100000000));
      sub.add_option("--seed", o->seed, "Random seed");
      sub.add_option("--method", o->method, "Only this method (exact or bisection)")
          ->check(CLI::IsMember({"exact", "bisection"}));
      sub.add_option("--octree", o->octree, "Only this octree mode (full, leaves or off)")
          ->check(CLI::IsMember({"full", "leaves", "off"}));
      return std::function<int()>([o, cache]() {
        o->cache = resolveCacheOption(cache, o->cache);
        return runBenchSegments(*o);
      });
    });

}  // namespace
}  // namespace sdfccd::cli
