/// @file
/// @brief `sdfccd bench bullet --part scaling`: how the cost of a pile grows with its bodies and
/// with the narrowphase's threads, beside Bullet's convex hulls in the same run.
///
/// @details 20, 80 and 320 bunnies (drop-bunnies' bunny: 777 points, 128^3 field; the shipped scene's 20
/// orientations repeated) dropped from a grid of layers into a pile, 1.5 s simulated:
/// - penalty mode at 1 ms and solver mode at 1/240 s, each with the project's contact defaults (what a new world
///   gets), on 1 and on 2 narrowphase threads (ContactSettings::threads; identical results);
/// - the convex-hull world (gimpact_peer.h, PeerShape::ConvexHull: Bullet's btConvexHullShape of the bunny's hull)
///   at 1/240 s, Bullet's own single-threaded step.
/// Per run: wall time of the steps, thread CPU of the stepping thread and CPU of the whole process (our pool's threads
/// included), step time per body, CCD queries per step, the real-time factor (simulated / wall), the share of the wall
/// time spent in the parallel batches (the rest is serial: Bullet's own step, the planning and the serial consumption
/// of the results; Amdahl's bound) and the parallel speedup (wall on 1 thread / wall on 2). The project's targets
/// (docs/benchmarks.md, scaling) are printed beside ours: 80 bunnies at >= 0.5x real time in penalty mode, >= 1x in
/// solver mode, speedup >= 1.8x on 2 cores (on an idle machine; the load average is printed with the results). A CSV
/// (rows of the bench's CSV) and a PNG plot of step time per body against bodies. With `repeat` > 1 every world runs
/// that many times, the worlds of a pile size in turns (so that a slow spell of the shared machine falls on all of
/// them), and each row is the run of median wall time.
#pragma once

#if __has_include("sdfccd/bullet/scene_world.h")  // built only with the Bullet plugin
#include <functional>
#include <string>
#include <vector>

namespace sdfccd::cli {

struct ScalingBenchOptions {
  bool quick = false;                      ///< 4 and 12 bunnies, 0.1 s simulated: a smoke test
  std::string scenes = "assets/scenes";    ///< where drop-bunnies.json is
  std::string cache;                       ///< body model cache ("": none)
  std::vector<int> bodies;                 ///< the pile sizes (empty: 20, 80, 320; --quick: 4, 12)
  std::string plot = "bench_scaling.png";  ///< the PNG ("": none)
  int repeat = 1;  ///< runs of each world, taken in turns; each row is the run of median wall time
};

/// Receives one CSV row (part, item, key, value).
using ScalingCsvSink = std::function<void(const std::string&, const std::string&, const std::string&, double)>;

void runScalingBench(const ScalingBenchOptions& options, const ScalingCsvSink& csv);

}  // namespace sdfccd::cli

#endif
