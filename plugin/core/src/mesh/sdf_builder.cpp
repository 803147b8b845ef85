/// @file
/// @brief buildSdf: the grid layout, then the distance pass (sdf_distance_pass.cpp) and the sign
/// (sdf_sign.cpp) (paper Section 5, Table 1).
///
/// @details Sign: the pseudonormal of the closest feature, right in the distance pass (closed meshes); or a
/// second pass with the fast winding number per node (open meshes); a block whose ball holds no surface and
/// whose centre winding number is clearly 0 or 1 (|w - 1/2| > 1/4) takes that sign for all its nodes (w is
/// continuous off the surface and, on closed parts, constant). The automatic choice checks a closed mesh
/// first (sdf_sign.h): when it intersects itself, or its pseudonormal signs disagree with the winding number
/// away from the surface, the distances are re-signed by the winding number.
#include "sdfccd/mesh/sdf_builder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>

#include "mesh_pseudonormals.h"
#include "sdf_build_blocks.h"
#include "sdf_distance_pass.h"
#include "sdf_sign.h"
#include "sdfccd/error.h"
#include "sdfccd/parallel_for.h"
#include "sdfccd/tolerances.h"
#include "triangle_bvh.h"
#include "winding_number.h"

namespace sdfccd {

using detail::Block;
using detail::FastWindingNumber;
using detail::MeshPseudonormals;
using detail::ProgressReporter;
using detail::TriangleBvh;

const char* toString(SdfSignMethod method) {
  switch (method) {
    case SdfSignMethod::Automatic:
      return "automatic";
    case SdfSignMethod::Pseudonormal:
      return "pseudonormal";
    case SdfSignMethod::WindingNumber:
      return "winding-number";
  }
  return "?";
}

bool isClosedAndOriented(const TriangleMesh& mesh) {
  // Every directed edge must occur once, and its reverse once.
  std::vector<std::uint64_t> directed;
  directed.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      directed.push_back(static_cast<std::uint64_t>(static_cast<std::uint32_t>(t[e])) << 32 |
                         static_cast<std::uint32_t>(t[(e + 1) % 3]));
    }
  }
  std::sort(directed.begin(), directed.end());
  if (std::adjacent_find(directed.begin(), directed.end()) != directed.end()) return false;
  for (const std::uint64_t key : directed) {
    const std::uint64_t reverse = (key << 32) | (key >> 32);
    if (!std::binary_search(directed.begin(), directed.end(), reverse)) return false;
  }
  return !directed.empty();
}

SdfGridLayout computeSdfGridLayout(const Box3& meshBounds, const SdfBuildSettings& settings) {
  if (settings.resolution < 1 || settings.resolution > 4096) {
    throw Error("resolution must be in 1..4096 cells, got " + std::to_string(settings.resolution));
  }
  if (settings.padding < 0 || settings.padding > 4096) {
    throw Error("padding must be in 0..4096 cells, got " + std::to_string(settings.padding));
  }
  if (meshBounds.isEmpty() || !meshBounds.min().allFinite() || !meshBounds.max().allFinite()) {
    throw Error("mesh bounds are empty or not finite");
  }
  const Vec3 extent = meshBounds.sizes();
  const double longest = extent.maxCoeff();
  if (!(longest > 0.0)) throw Error("mesh has zero extent (all vertices coincide)");
  SdfGridLayout layout;
  layout.spacing = longest / settings.resolution;
  const Vec3 centre = meshBounds.center();
  for (int a = 0; a < 3; ++a) {
    // The longest axis gets exactly `resolution` cells; the others the fewest that cover the mesh. The mesh
    // is centred in the grid.
    const double cellsExact = extent[a] / layout.spacing;
    long long cells = static_cast<long long>(std::ceil(cellsExact - tolerance::kCountRounding));
    cells = std::max(cells, 1LL) + 2LL * settings.padding;
    if (cells + 1 > 65536) throw Error("grid would have more than 65536 nodes along an axis");
    layout.nodeCounts[a] = static_cast<int>(cells + 1);
    layout.origin[a] = centre[a] - 0.5 * static_cast<double>(cells) * layout.spacing;
  }
  const double bytes = static_cast<double>(layout.nodeCounts.x()) * layout.nodeCounts.y() * layout.nodeCounts.z() * 4.0;
  if (bytes > static_cast<double>(settings.maxMemoryBytes)) {
    std::ostringstream s;
    s << "grid of " << layout.nodeCounts.x() << " x " << layout.nodeCounts.y() << " x " << layout.nodeCounts.z()
      << " nodes needs " << bytes / (1024.0 * 1024.0) << " MiB, over the limit of "
      << static_cast<double>(settings.maxMemoryBytes) / (1024.0 * 1024.0) << " MiB";
    throw Error(s.str());
  }
  return layout;
}

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The largest |coordinate| of the grid's nodes and the mesh's vertices (sizes the float allowances).
double largestCoordinate(const TriangleMesh& mesh, const SdfGridLayout& layout) {
  double largest = 0.0;
  for (int a = 0; a < 3; ++a) {
    largest = std::max({largest, std::fabs(layout.origin[a]),
                        std::fabs(layout.origin[a] + layout.spacing * (layout.nodeCounts[a] - 1))});
  }
  for (const Vec3& v : mesh.vertices) largest = std::max(largest, v.cwiseAbs().maxCoeff());
  return largest;
}

}  // namespace

SdfBuildResult buildSdf(const TriangleMesh& mesh, const SdfBuildSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  checkMesh(mesh, "cannot build an SDF");
  if (!(settings.windingAccuracy > 1.0) || !std::isfinite(settings.windingAccuracy)) {
    throw Error("winding accuracy (beta) must be finite and > 1");
  }
  const SdfGridLayout layout = computeSdfGridLayout(mesh.bounds(), settings);
  const int threads = settings.threads > 0 ? settings.threads : defaultThreadCount();

  SdfBuildResult result;
  SdfBuildStats& stats = result.stats;
  stats.threads = threads;
  stats.triangles = mesh.triangles.size();
  stats.signMethod = settings.signMethod;
  const bool automatic = settings.signMethod == SdfSignMethod::Automatic;
  if (automatic) {
    stats.signMethod = isClosedAndOriented(mesh) ? SdfSignMethod::Pseudonormal : SdfSignMethod::WindingNumber;
  }

  const TriangleBvh bvh(mesh);
  // A closed mesh that crosses itself has buried faces whose pseudonormals point the wrong way (sdf_sign.h).
  if (automatic && stats.signMethod == SdfSignMethod::Pseudonormal) {
    stats.selfIntersections = detail::countSelfIntersections(mesh, bvh, threads);
    if (stats.selfIntersections > 0) stats.signMethod = SdfSignMethod::WindingNumber;
  }
  bool winding = stats.signMethod == SdfSignMethod::WindingNumber;
  std::unique_ptr<MeshPseudonormals> normals;
  if (!winding) normals = std::make_unique<MeshPseudonormals>(mesh);

  const std::size_t nodeCount = layout.nodeCount();
  std::vector<float> values(nodeCount);
  const std::vector<Block> blocks = detail::makeBlocks(layout.nodeCounts);
  // Progress: distances to 0.7 before a winding pass, to 0.9 before the automatic check (a fallback pass
  // then fills the rest), else to 1.
  const double distanceEnd = winding ? 0.7 : (automatic ? 0.9 : 1.0);
  ProgressReporter distanceProgress(settings.progress, blocks.size(), 0.0, distanceEnd);
  const detail::DistancePassStats pass = detail::computeNodeDistances(
      bvh, layout, normals.get(), largestCoordinate(mesh, layout), blocks, threads, distanceProgress, values.data());
  stats.distanceSeconds = secondsSince(start);
  stats.meanCandidates = pass.meanCandidates;

  const auto signStart = std::chrono::steady_clock::now();
  std::size_t signBytes = normals ? normals->memoryBytes() : 0;
  std::unique_ptr<FastWindingNumber> windingNumber;
  if (automatic && !winding) {
    // Nested shells of one orientation do not cross but still fool the pseudonormal: check the blocks away
    // from the surface against the winding number (one evaluation per block).
    windingNumber = std::make_unique<FastWindingNumber>(bvh, settings.windingAccuracy);
    stats.inconsistentSignNodes =
        detail::countSignsDisagreeingWithWinding(bvh, *windingNumber, layout, blocks, threads, values.data());
    if (stats.inconsistentSignNodes > 0) {
      for (float& v : values) v = std::fabs(v);
      stats.signMethod = SdfSignMethod::WindingNumber;
      winding = true;
    }
  }
  if (winding) {
    if (!windingNumber) windingNumber = std::make_unique<FastWindingNumber>(bvh, settings.windingAccuracy);
    signBytes = windingNumber->memoryBytes();
    ProgressReporter signProgress(settings.progress, blocks.size(), distanceEnd, 1.0);
    detail::signByWindingNumber(bvh, *windingNumber, settings.windingThreshold, layout, blocks, threads, signProgress,
                                values.data());
  }
  stats.signSeconds = secondsSince(signStart);

  result.grid = std::make_shared<const SdfGrid>(layout.nodeCounts, layout.origin, layout.spacing, std::move(values));
  stats.gridBytes = result.grid->memoryBytes();
  stats.peakExtraBytes = bvh.memoryBytes() + pass.scratchBytes + signBytes;
  stats.seconds = secondsSince(start);
  if (settings.progress) settings.progress(1.0);
  return result;
}

}  // namespace sdfccd
