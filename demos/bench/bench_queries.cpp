/// @file
/// @brief `sdfccd bench queries`: btCollisionWorld::rayTest and convexSweepTest against an SdfccdShape beside a
/// btBvhTriangleMeshShape of the same mesh (the target: within 2x of Bullet's).
///
/// @details One bunny (assets/meshes/bunny.off, scale 0.2, the drop scenes' resolution 128 by default) at a
/// tilted pose in two collision worlds: as our shape, and as Bullet's BVH triangle mesh of the very same
/// body-frame triangles. The same random queries run in both: rays from a sphere of twice the bunny's size
/// towards random points near it (about half hit), and sphere and box sweeps along the same kind of paths.
/// Closest-hit callbacks, wall time per query over all queries, best of --repeats runs. Hit counts are
/// printed for both worlds: they agree for rays and for sweeps without a turn (the answers are the triangle
/// mesh's, tests/bullet/shape_queries_test.cpp). The sweeps here also turn from one orientation to another;
/// Bullet's BVH traversal boxes the shape at its end orientation only and can skip a triangle the turning shape
/// touches (one box sweep in 300 with the default seed), which ours, bounding the shape by a sphere, hands over.
#if __has_include("sdfccd/bullet/sdfccd_shape.h")  // built only with the Bullet plugin
#include <btBulletCollisionCommon.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench/cache_option.h"
#include "cli/bench_registry.h"
#include "sdfccd/bullet/bullet_pose.h"
#include "sdfccd/bullet/sdfccd_shape.h"
#include "sdfccd/error.h"
#include "sdfccd/output_file.h"

namespace sdfccd::cli {
namespace {

struct BenchQueriesOptions {
  int rays = 20000;
  int sweeps = 300;
  int repeats = 3;
  int resolution = 128;
  std::string mesh = "assets/meshes/bunny.off";
  std::string csv = "bench_queries.csv";
  std::string cache;
};

/// A collision world holding one object.
struct OneObjectWorld {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &configuration};
  btCollisionObject object;
  OneObjectWorld(btCollisionShape* shape, const btTransform& pose) {
    object.setCollisionShape(shape);
    object.setWorldTransform(pose);
    world.addCollisionObject(&object);
  }
  ~OneObjectWorld() { world.removeCollisionObject(&object); }
};

struct Path {
  btTransform from, to;
};

/// Paths from a sphere of radius `size` around `centre` towards random points near it, extended past them.
std::vector<Path> randomPaths(int count, const btVector3& centre, btScalar size, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> n;
  std::uniform_real_distribution<float> u(0, 1);
  auto unit = [&] { return btVector3(n(rng), n(rng), n(rng)).normalized(); };
  std::vector<Path> paths;
  for (int i = 0; i < count; ++i) {
    const btVector3 from = centre + unit() * size;
    const btVector3 target = centre + unit() * (0.4f * size * u(rng));
    paths.push_back({btTransform(btQuaternion(unit(), u(rng) * 3), from),
                     btTransform(btQuaternion(unit(), u(rng) * 3), from + (target - from) * 1.6f)});
  }
  return paths;
}

/// Best-of-`repeats` seconds per call of `run` over all paths; `hits` counts the hits of the last run.
template <class Run>
double timePerQuery(const std::vector<Path>& paths, int repeats, int& hits, Run&& run) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    hits = 0;
    const auto start = std::chrono::steady_clock::now();
    for (const Path& p : paths) hits += run(p) ? 1 : 0;
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best / double(std::max<std::size_t>(1, paths.size()));
}

int runBenchQueries(const BenchQueriesOptions& o) {
  if (o.rays < 1 || o.sweeps < 0 || o.repeats < 1 || o.resolution < 8) {
    throw Error("--rays must be >= 1, --sweeps >= 0, --repeats >= 1, --resolution >= 8");
  }
  std::printf("sdfccd bench queries -- %s\n", machineDescription().c_str());
  BodyModelSettings settings;
  settings.resolution = o.resolution;
  settings.points = 777;
  settings.scale = 0.2;
  settings.cacheDir = o.cache;
  const auto model = BodyModel::buildFromMeshFile(o.mesh, settings);
  const TriangleMesh& mesh = model->meshInBody();
  btTriangleMesh triangles;
  for (const auto& t : mesh.triangles) {
    triangles.addTriangle(bullet::toBtVector3(mesh.vertices[std::size_t(t[0])]), bullet::toBtVector3(mesh.vertices[std::size_t(t[1])]),
                          bullet::toBtVector3(mesh.vertices[std::size_t(t[2])]));
  }
  btBvhTriangleMeshShape bvhShape(&triangles, true);
  bullet::SdfccdShape oursShape(model);
  const btTransform pose(btQuaternion(btVector3(1, 2, 3).normalized(), 0.7f), btVector3(0.3f, -0.2f, 0.1f));
  OneObjectWorld ours(&oursShape, pose), bvh(&bvhShape, pose);
  const btVector3 centre = pose(bullet::toBtVector3(model->boundsInBody().center()));
  const btScalar size = btScalar(model->boundsInBody().diagonal().norm());
  std::printf("%s: %zu triangles, field %d cells on the longest side (cell %.3g m)\n", o.mesh.c_str(),
              mesh.triangles.size(), o.resolution, model->cellSize());

  std::ostringstream csv;
  csv << "query,shape,seconds_per_query,hits,queries\n";
  auto report = [&](const char* query, double oursSeconds, int oursHits, double bvhSeconds, int bvhHits,
                    std::size_t count) {
    std::printf("  %-12s ours %8.4f ms (%d hits)   btBvhTriangleMeshShape %8.4f ms (%d hits)   ratio %.2f\n", query,
                oursSeconds * 1e3, oursHits, bvhSeconds * 1e3, bvhHits, oursSeconds / bvhSeconds);
    csv << query << ",sdfccd," << oursSeconds << "," << oursHits << "," << count << "\n";
    csv << query << ",bvh," << bvhSeconds << "," << bvhHits << "," << count << "\n";
  };
  // The first query builds the shape's lookup tables: not part of the per-query cost.
  {
    btCollisionWorld::ClosestRayResultCallback warm(centre, centre);
    ours.world.rayTest(centre + btVector3(size, 0, 0), centre, warm);
  }
  std::printf("per query (best of %d runs; closest-hit callbacks):\n", o.repeats);
  const std::vector<Path> rayPaths = randomPaths(o.rays, centre, size, 15);
  auto ray = [](btCollisionWorld& world) {
    return [&world](const Path& p) {
      btCollisionWorld::ClosestRayResultCallback cb(p.from.getOrigin(), p.to.getOrigin());
      world.rayTest(p.from.getOrigin(), p.to.getOrigin(), cb);
      return cb.hasHit();
    };
  };
  int oursHits = 0, bvhHits = 0;
  const double oursRay = timePerQuery(rayPaths, o.repeats, oursHits, ray(ours.world));
  const double bvhRay = timePerQuery(rayPaths, o.repeats, bvhHits, ray(bvh.world));
  report("rayTest", oursRay, oursHits, bvhRay, bvhHits, rayPaths.size());
  if (o.sweeps > 0) {
    btSphereShape sphere(0.03f * size);
    btBoxShape box(btVector3(0.04f, 0.02f, 0.03f) * size);
    const std::vector<Path> sweepPaths = randomPaths(o.sweeps, centre, size, 16);
    for (btConvexShape* shape : {static_cast<btConvexShape*>(&sphere), static_cast<btConvexShape*>(&box)}) {
      auto sweep = [shape](btCollisionWorld& world) {
        return [&world, shape](const Path& p) {
          btCollisionWorld::ClosestConvexResultCallback cb(p.from.getOrigin(), p.to.getOrigin());
          world.convexSweepTest(shape, p.from, p.to, cb);
          return cb.hasHit();
        };
      };
      const double oursSweep = timePerQuery(sweepPaths, o.repeats, oursHits, sweep(ours.world));
      const double bvhSweep = timePerQuery(sweepPaths, o.repeats, bvhHits, sweep(bvh.world));
      report(shape == &sphere ? "sweep sphere" : "sweep box", oursSweep, oursHits, bvhSweep, bvhHits,
             sweepPaths.size());
    }
  }
  if (!o.csv.empty()) {
    writeOutputFile(o.csv, csv.str());
    std::printf("wrote %s\n", o.csv.c_str());
  }
  return 0;
}

const BenchRegistrar bench_queriesRegistrar(
    "queries", "rayTest and convexSweepTest against an SdfccdShape vs a btBvhTriangleMeshShape of the same mesh",
    [](CLI::App& sub) {
      auto o = std::make_shared<BenchQueriesOptions>();
      sub.add_option("--rays", o->rays, "Random rays (default 20000)");
      sub.add_option("--sweeps", o->sweeps, "Random sweeps per convex shape (default 300; 0: none)");
      sub.add_option("--repeats", o->repeats, "Runs of each set; the best is reported (default 3)");
      sub.add_option("--resolution", o->resolution, "Field cells on the mesh's longest side (default 128)");
      sub.add_option("--mesh", o->mesh, "Closed mesh file (default assets/meshes/bunny.off)");
      sub.add_option("--out", o->csv, "CSV output (default bench_queries.csv; empty: none)");
      const CLI::Option* cache = addCacheOption(sub, o->cache, "Body model cache");
      return [o, cache]() {
        o->cache = resolveCacheOption(cache, o->cache);
        return runBenchQueries(*o);
      };
    });

}  // namespace
}  // namespace sdfccd::cli
#endif
