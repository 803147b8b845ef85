/// @file
/// @brief The segment CCD experiments shared by `sdfccd bench segments` and the report's `segments` section
/// (paper Table 2, Sections 3.1-3.2): segment sets, timed queries, the cached bunny fields, and a dense
/// brute-force reference for first hits.
///
/// @details The brute-force reference is independent of the library's cell walk and cubic: it samples the
/// trilinear field pointwise (SdfGrid::interpolate) along the segment, `samplesPerCell` samples per cell
/// length, takes the first sample in contact (phi <= sigma, inside the grid's closed box) and refines the
/// crossing by bisection between it and the sample before. A dip narrower than the sample spacing can escape
/// it; compareWithReference() therefore accepts a method's earlier hit when the field at that fraction is in
/// contact ("confirmed", the sampler stepped over it), and counts it apart.
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "sdfccd/ccd/segment_ccd.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/field/sdf_grid.h"

namespace sdfccd::cli {

/// One query's motion, both ends in the field's frame.
struct Segment {
  Vec3 p0, p1;
};

/// Timing of one (method, octree mode) over a segment set.
struct SegmentTiming {
  double microseconds = 0.0;      ///< per segment, CPU time of the calling thread (us)
  double wallMicroseconds = 0.0;  ///< per segment, wall-clock time (us)
  long long hits = 0;             ///< segments with a first hit (or starting inside)
  std::vector<float> fractions;   ///< first hit per segment, -1 when none (only when asked for)
};

/// Runs the first-hit query (sigma = 0) on the first `count` segments, one thread, and times it.
SegmentTiming timeSegmentQueries(const GridField& field, const std::vector<Segment>& segments, CcdMethod method,
                                 OctreeMode octree, std::size_t count, bool keepFractions);

/// First hits of bisection against exact: missed (exact hits, bisection not), misplaced (> 1% of a cell apart
/// along the segment), spurious (bisection hits, exact not).
struct BisectionVsExact {
  long long exactHits = 0, missed = 0, misplaced = 0, spurious = 0;
};
BisectionVsExact compareBisectionToExact(const GridField& field, const std::vector<Segment>& segments,
                                         std::size_t count);

/// Segments between uniformly random points of `box` (paper Table 2's protocol).
std::vector<Segment> randomSegmentsInBox(const Box3& box, std::size_t count, unsigned seed);
/// Haptic-rate segments: start outside the object within 2 cells of the surface, random direction, length up
/// to 2 cells (a shell point's step at 1 kHz).
std::vector<Segment> hapticSegments(const GridField& field, std::size_t count, unsigned seed);
/// Segments from uniformly random starts in `box`, random direction, length uniform in [0, maxLength].
std::vector<Segment> shortRandomSegments(const Box3& box, double maxLength, std::size_t count, unsigned seed);

/// A grid of `cells`^3 cells of unit size whose node values are independent and uniform in [-1, 1]: several
/// roots per cell along a segment, the case that defeats bisection (paper Fig. 2).
std::shared_ptr<const SdfGrid> randomValueGrid(int cells, unsigned seed);

/// The bunny's field at `resolution`^3 cells, padding 0 (the paper's grids): loaded from
/// `cacheDir`/bunny_<resolution>_pad0.sdf, else built from `meshPath` with `threads` threads and cached there
/// (when cacheDir is not empty). `log` (may be null) gets one line per load or build. Throws sdfccd::Error when
/// there is no cached field and the tool was built without mesh loading.
std::shared_ptr<const SdfGrid> cachedBunnyField(const std::filesystem::path& cacheDir,
                                                const std::filesystem::path& meshPath, int resolution, int threads,
                                                std::FILE* log);

/// The brute-force reference's first hit of one segment.
struct ReferenceFirstHit {
  bool hit = false;
  double fraction = 1.0;  ///< first t in [0, 1] with phi <= sigma (1 when none)
};
ReferenceFirstHit bruteForceFirstHit(const SdfGrid& grid, const Segment& segment, double sigma, int samplesPerCell);
/// The reference for every segment, computed on `threads` threads.
std::vector<ReferenceFirstHit> bruteForceFirstHits(const SdfGrid& grid, const std::vector<Segment>& segments,
                                                   double sigma, int samplesPerCell, int threads);

/// One query method's first hits against the reference.
struct ReferenceComparison {
  long long segments = 0;
  long long referenceHits = 0;  ///< segments the reference finds in contact
  long long methodHits = 0;
  long long missed = 0;     ///< reference hits, the method does not
  long long wrong = 0;      ///< both hit, more than 1% of a cell apart (and not a confirmed earlier contact)
  long long spurious = 0;   ///< the method hits where the field is not in contact and the reference has none
  long long confirmed = 0;  ///< the method hits earlier than the reference, on a dip the samples stepped over
};
ReferenceComparison compareWithReference(const GridField& field, const std::vector<Segment>& segments,
                                         const std::vector<ReferenceFirstHit>& reference,
                                         const SegmentCcdSettings& settings);

}  // namespace sdfccd::cli
