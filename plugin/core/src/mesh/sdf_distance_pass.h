/// @file
/// @brief The distance pass of the SDF builder: the exact distance of every node to the triangle set, signed by
/// the pseudonormal of the closest feature when pseudonormals are given. Internal header of the SDF builder.
#pragma once

#include <cstddef>
#include <vector>

#include "mesh_pseudonormals.h"
#include "sdf_build_blocks.h"
#include "sdfccd/mesh/sdf_builder.h"
#include "triangle_bvh.h"

namespace sdfccd::detail {

/// Figures of the distance pass.
struct DistancePassStats {
  double meanCandidates = 0.0;   ///< mean candidate triangles per block
  std::size_t scratchBytes = 0;  ///< bytes of the per-thread scratch
};

/// Writes the exact distance of every node of `layout` to `outValues` (nodeCount() floats, i fastest),
/// negative where the pseudonormal says inside when `normals` is set, unsigned otherwise. `largestCoordinate`
/// bounds every |coordinate| of the nodes and vertices (it sizes the float rounding allowances).
DistancePassStats computeNodeDistances(const TriangleBvh& bvh, const SdfGridLayout& layout,
                                       const MeshPseudonormals* normals, double largestCoordinate,
                                       const std::vector<Block>& blocks, int threads, ProgressReporter& progress,
                                       float* outValues);

}  // namespace sdfccd::detail
