/// @file
/// @brief buildSdf: the exact signed distance field of a triangle mesh on a uniform grid (paper Section 5,
/// Table 1).
///
/// @details Every node value is the exact Euclidean distance (computed in double, stored as float) from the
/// node to the closest point of the triangle set, negative inside. The grid spans the mesh's bounding box
/// plus `padding` cells on every side; cells are cubes whose edge is the longest box side / `resolution`.
///
/// Algorithm (details in sdf_builder.cpp): the grid is processed in blocks of 8^3 nodes on worker threads,
/// each refined like an octree (8 -> 4 -> 2 nodes per side). A box of nodes keeps the candidate triangles
/// whose bounding box lies within d(centre) + half-diagonal of it (an upper bound on every node's distance);
/// the block's list comes from a BVH, each child's is filtered from its parent's. Each node then finds its
/// exact closest triangle among its 2^3 box's candidates: float box lower bounds (SoA, 8 lanes), a float
/// point-triangle screen of the survivors, and the exact double closest point for the few left, warm-started
/// with the previous node's closest triangle. Float bounds carry rounding allowances, so every value equals
/// the brute-force minimum over all triangles (the tests check this).
///
/// Sign: on closed (watertight, consistently oriented) meshes the sign of (node - closest point) . n, with n
/// the angle-weighted pseudonormal of the closest feature (Baerentzen & Aanaes 2005), exact and cheap. On
/// open meshes and meshes with holes the fast generalized winding number (Jacobson et al. 2013; Barill et al.
/// 2018 far-field dipole approximation on the BVH) decides: inside where w >= 0.5; a block whose bounding
/// ball holds no surface and whose centre has w clearly 0 or 1 (|w - 1/2| > 1/4) gives that sign to all its
/// nodes (w is continuous off the surface), every other node is evaluated on its own.
///
/// The automatic choice trusts the pseudonormal only on a closed mesh that passes two checks, since a closed
/// mesh that intersects itself (two overlapping cubes in one file) or holds nested shells of one orientation
/// has buried faces whose pseudonormals give inside nodes a positive sign: no pair of triangles may cross
/// (BVH pairs, an edge strictly through another triangle), and in every block of nodes away from the surface
/// the pseudonormal signs must agree with the winding number at the block's centre. Otherwise the winding
/// number signs every node (SdfBuildStats::selfIntersections and inconsistentSignNodes say why).
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "sdfccd/field/sdf_grid.h"
#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"
#include "sdfccd/progress.h"

namespace sdfccd {

/// How the inside/outside sign is decided.
enum class SdfSignMethod {
  Automatic,      ///< Pseudonormal on closed meshes that pass the checks below, WindingNumber otherwise
  Pseudonormal,   ///< angle-weighted pseudonormal of the closest feature (exact on closed, oriented meshes)
  WindingNumber,  ///< generalized winding number >= 0.5 (robust to holes and open boundaries)
};

/// "pseudonormal", "winding-number" or "automatic".
const char* toString(SdfSignMethod method);

/// Settings of buildSdf.
struct SdfBuildSettings {
  int resolution = 128;  ///< cells along the longest side of the mesh's box (1..4096)
  int padding = 4;       ///< extra cells around the mesh's box on each side (>= 0)
  int threads = 0;       ///< worker threads, 0 = all hardware threads
  SdfSignMethod signMethod = SdfSignMethod::Automatic;
  double windingThreshold = 0.5;  ///< inside where the winding number is >= this (WindingNumber)
  double windingAccuracy = 2.0;   ///< Barill et al.'s beta: far-field when distance > beta * cluster radius
  std::size_t maxMemoryBytes = std::size_t(16) << 30;  ///< bytes; larger grids are refused before allocating
  ProgressCallback progress;                           ///< called with the fraction done (optional)
};

/// The grid a build will produce, known before any work (lets callers check memory first).
struct SdfGridLayout {
  Vec3i nodeCounts = Vec3i::Zero();  ///< nodes along x, y, z
  Vec3 origin = Vec3::Zero();        ///< position of node (0,0,0), mesh frame (model units)
  double spacing = 0.0;              ///< cell edge (model units)
  std::size_t nodeCount() const {
    return static_cast<std::size_t>(nodeCounts.x()) * static_cast<std::size_t>(nodeCounts.y()) *
           static_cast<std::size_t>(nodeCounts.z());
  }
  std::size_t memoryBytes() const { return nodeCount() * sizeof(float); }  ///< bytes of the values
};

/// The layout for a mesh box and settings. Throws sdfccd::Error on bad settings (resolution outside 1..4096,
/// negative padding, an empty or non-finite box, or a grid over settings.maxMemoryBytes).
SdfGridLayout computeSdfGridLayout(const Box3& meshBounds, const SdfBuildSettings& settings);

/// Figures of one build.
struct SdfBuildStats {
  double seconds = 0.0;            ///< wall-clock time of the whole build (s)
  double distanceSeconds = 0.0;    ///< time of the distance pass and the automatic crossing check (s)
  double signSeconds = 0.0;        ///< time of the sign pass and the automatic winding-number check (s)
  std::size_t gridBytes = 0;       ///< bytes of the grid values
  std::size_t peakExtraBytes = 0;  ///< bytes of the temporary structures (BVH, candidates, ...), estimated
  SdfSignMethod signMethod = SdfSignMethod::Automatic;  ///< the method actually used
  int threads = 0;                                      ///< worker threads used
  std::size_t triangles = 0;                            ///< triangles of the mesh
  double meanCandidates = 0.0;                          ///< mean candidate triangles per block (diagnostic)
  /// Automatic sign on a closed mesh: pairs of triangles that cross (an edge strictly through another's
  /// interior; neighbours sharing a vertex are not tested). Any makes the build use the winding number.
  std::size_t selfIntersections = 0;
  /// Automatic sign on a closed mesh without crossings: nodes, in blocks away from the surface, whose
  /// pseudonormal sign disagreed with the winding number (nested shells of one orientation). Any makes the
  /// build re-sign every node by the winding number.
  std::size_t inconsistentSignNodes = 0;
};

/// Result of buildSdf. Keep it (or a copy of `grid`) alive: `const SdfGrid& g = *buildSdf(m, s).grid;`
/// dangles once the temporary result is destroyed.
struct SdfBuildResult {
  std::shared_ptr<const SdfGrid> grid;  ///< the field
  SdfBuildStats stats;
};

/// Builds the signed distance field of `mesh` (which should have passed repairMesh). Throws sdfccd::Error
/// on an empty mesh, non-finite vertices or bad settings.
SdfBuildResult buildSdf(const TriangleMesh& mesh, const SdfBuildSettings& settings);

/// True when every edge of `mesh` is shared by exactly two faces that traverse it in opposite directions
/// (the condition under which the pseudonormal sign is exact).
bool isClosedAndOriented(const TriangleMesh& mesh);

}  // namespace sdfccd
