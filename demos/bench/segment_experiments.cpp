/// @file
/// @brief Segment sets, timed queries, cached bunny fields and the brute-force first-hit reference (see
/// segment_experiments.h).
#include "bench/segment_experiments.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/field/sdf_file.h"
#include "sdfccd/mesh/sdf_builder.h"
#include "sdfccd/parallel_for.h"
#include "sdfccd/thread_cpu_time.h"
#if __has_include("sdfccd/io/mesh_loader.h")
#include "sdfccd/io/mesh_loader.h"
#define SDFCCD_SEGMENT_EXPERIMENTS_HAS_IO 1
#endif

namespace sdfccd::cli {

namespace fs = std::filesystem;

SegmentTiming timeSegmentQueries(const GridField& field, const std::vector<Segment>& segments, CcdMethod method,
                                 OctreeMode octree, std::size_t count, bool keepFractions) {
  SegmentCcdSettings settings;
  settings.sigma = 0.0;
  settings.method = method;
  settings.octree = octree;
  settings.mode = CcdMode::FirstHit;
  count = std::min(count, segments.size());
  SegmentTiming timing;
  if (keepFractions) timing.fractions.assign(count, -1.0f);
  SegmentCcdResult r;
  const auto start = std::chrono::steady_clock::now();
  const double cpuStart = threadCpuSeconds();
  for (std::size_t n = 0; n < count; ++n) {
    field.intersectSegment(segments[n].p0, segments[n].p1, settings, r);
    if (r.hit()) {
      ++timing.hits;
      if (keepFractions) timing.fractions[n] = static_cast<float>(r.fraction);
    }
  }
  const double cpu = threadCpuSeconds() - cpuStart;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  timing.microseconds = 1e6 * cpu / static_cast<double>(std::max<std::size_t>(count, 1));
  timing.wallMicroseconds = 1e6 * seconds / static_cast<double>(std::max<std::size_t>(count, 1));
  return timing;
}

BisectionVsExact compareBisectionToExact(const GridField& field, const std::vector<Segment>& segments,
                                         std::size_t count) {
  SegmentCcdSettings exact, bisection;
  exact.mode = bisection.mode = CcdMode::FirstHit;
  bisection.method = CcdMethod::Bisection;
  BisectionVsExact m;
  SegmentCcdResult a, b;
  count = std::min(count, segments.size());
  for (std::size_t n = 0; n < count; ++n) {
    field.intersectSegment(segments[n].p0, segments[n].p1, exact, a);
    field.intersectSegment(segments[n].p0, segments[n].p1, bisection, b);
    if (a.hit()) ++m.exactHits;
    if (a.hit() && !b.hit()) ++m.missed;
    if (!a.hit() && b.hit()) ++m.spurious;
    if (a.hit() && b.hit()) {
      const double length = (segments[n].p1 - segments[n].p0).norm();
      if (std::abs(a.fraction - b.fraction) * length > 0.01 * field.spacing()) ++m.misplaced;
    }
  }
  return m;
}

std::vector<Segment> randomSegmentsInBox(const Box3& box, std::size_t count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 size = box.max() - box.min();
  std::vector<Segment> s(count);
  for (auto& seg : s) {
    seg.p0 = box.min() + size.cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    seg.p1 = box.min() + size.cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
  }
  return s;
}

std::vector<Segment> hapticSegments(const GridField& field, std::size_t count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> normal;
  const Box3 box = field.grid().box();
  const Vec3 size = box.max() - box.min();
  const double h = field.spacing();
  std::vector<Segment> s;
  s.reserve(count);
  for (std::size_t attempts = 0; s.size() < count && attempts < 1000 * count; ++attempts) {
    const Vec3 p0 = box.min() + size.cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    const double phi = field.distance(p0);
    if (!(phi > 0.0 && phi < 2.0 * h)) continue;
    Vec3 dir(normal(rng), normal(rng), normal(rng));
    if (dir.norm() == 0.0) continue;
    s.push_back({p0, p0 + (2.0 * h * u(rng)) * dir.normalized()});
  }
  return s;
}

std::vector<Segment> shortRandomSegments(const Box3& box, double maxLength, std::size_t count, unsigned seed) {
  std::vector<Segment> segments = randomSegmentsInBox(box, count, seed);
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto& s : segments) {
    const Vec3 direction = s.p1 - s.p0;
    if (direction.norm() > 0.0) s.p1 = s.p0 + direction.normalized() * maxLength * u(rng);
  }
  return segments;
}

std::shared_ptr<const SdfGrid> randomValueGrid(int cells, unsigned seed) {
  const int n = cells + 1;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<float> values(static_cast<std::size_t>(n) * n * n);
  for (auto& v : values) v = static_cast<float>(u(rng));
  return std::make_shared<const SdfGrid>(Vec3i(n, n, n), Vec3::Zero(), 1.0, std::move(values));
}

std::shared_ptr<const SdfGrid> cachedBunnyField(const fs::path& cacheDir, const fs::path& meshPath, int resolution,
                                                int threads, std::FILE* log) {
  const fs::path cached = cacheDir / ("bunny_" + std::to_string(resolution) + "_pad0.sdf");
  if (!cacheDir.empty() && fs::exists(cached)) {
    if (log) std::fprintf(log, "  loading %s\n", cached.string().c_str());
    return std::make_shared<const SdfGrid>(loadSdf(cached.string()));
  }
#ifdef SDFCCD_SEGMENT_EXPERIMENTS_HAS_IO
  if (log) {
    std::fprintf(log, "  building the bunny SDF at %d^3 from %s%s%s\n", resolution, meshPath.string().c_str(),
                 cacheDir.empty() ? "" : " (cached in ", cacheDir.empty() ? "" : (cached.string() + ")").c_str());
    std::fflush(log);
  }
  const TriangleMesh mesh = loadMesh(meshPath.string());
  SdfBuildSettings settings;
  settings.resolution = resolution;
  settings.padding = 0;
  settings.threads = threads;
  SdfBuildResult built = buildSdf(mesh, settings);
  if (!cacheDir.empty()) {
    std::error_code ec;
    fs::create_directories(cacheDir, ec);
    if (!ec) saveSdf(cached.string(), *built.grid);
  }
  return built.grid;
#else
  (void)meshPath;
  (void)threads;
  throw Error("no cached field '" + cached.string() + "' and the tool was built without mesh loading (assimp)");
#endif
}

ReferenceFirstHit bruteForceFirstHit(const SdfGrid& grid, const Segment& segment, double sigma, int samplesPerCell) {
  const Vec3 delta = segment.p1 - segment.p0;
  // Outside the grid's closed box a grid field has no contact (segment_ccd.h).
  auto inContact = [&](double t) {
    const Vec3 p = segment.p0 + t * delta;
    return grid.contains(p) && grid.interpolate(p) <= sigma;
  };
  ReferenceFirstHit r;
  if (inContact(0.0)) {
    r.hit = true;
    r.fraction = 0.0;
    return r;
  }
  const double cellsAlong = delta.norm() / grid.spacing();
  const long long samples = std::max<long long>(2, static_cast<long long>(std::ceil(cellsAlong * samplesPerCell)));
  for (long long s = 1; s <= samples; ++s) {
    const double t = static_cast<double>(s) / static_cast<double>(samples);
    if (!inContact(t)) continue;
    // Refine between the free sample before and this one (60 halvings: below double precision of t).
    double free = static_cast<double>(s - 1) / static_cast<double>(samples);
    double contact = t;
    for (int i = 0; i < 60 && contact - free > 0.0; ++i) {
      const double mid = 0.5 * (free + contact);
      if (mid <= free || mid >= contact) break;
      (inContact(mid) ? contact : free) = mid;
    }
    r.hit = true;
    r.fraction = contact;
    return r;
  }
  return r;
}

std::vector<ReferenceFirstHit> bruteForceFirstHits(const SdfGrid& grid, const std::vector<Segment>& segments,
                                                   double sigma, int samplesPerCell, int threads) {
  std::vector<ReferenceFirstHit> reference(segments.size());
  parallelFor(segments.size(), threads,
              [&](std::size_t n, int) { reference[n] = bruteForceFirstHit(grid, segments[n], sigma, samplesPerCell); });
  return reference;
}

ReferenceComparison compareWithReference(const GridField& field, const std::vector<Segment>& segments,
                                         const std::vector<ReferenceFirstHit>& reference,
                                         const SegmentCcdSettings& settings) {
  if (reference.size() != segments.size()) throw Error("compareWithReference: one reference per segment expected");
  const SdfGrid& grid = field.grid();
  const double h = grid.spacing();
  ReferenceComparison c;
  SegmentCcdResult r;
  for (std::size_t n = 0; n < segments.size(); ++n) {
    const Segment& s = segments[n];
    const ReferenceFirstHit& ref = reference[n];
    field.intersectSegment(s.p0, s.p1, settings, r);
    ++c.segments;
    if (ref.hit) ++c.referenceHits;
    if (r.hit()) ++c.methodHits;
    if (ref.hit && !r.hit()) {
      ++c.missed;
      continue;
    }
    if (!r.hit()) continue;
    // Is the field in contact at the method's answer? (a root computed in double on float node values lies
    // on the level set to far better than 1e-6 of a cell)
    const Vec3 p = s.p0 + r.fraction * (s.p1 - s.p0);
    const bool inContact = grid.contains(p) && grid.interpolate(p) - settings.sigma <= 1e-6 * h;
    const double length = (s.p1 - s.p0).norm();
    if (!ref.hit) {
      (inContact ? c.confirmed : c.spurious) += 1;
      continue;
    }
    const double apart = std::abs(r.fraction - ref.fraction) * length;
    if (apart <= 0.01 * h) continue;
    if (r.fraction < ref.fraction && inContact) {
      ++c.confirmed;
    } else {
      ++c.wrong;
    }
  }
  return c;
}

}  // namespace sdfccd::cli
