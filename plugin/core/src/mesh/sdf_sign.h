/// @file
/// @brief The sign of the SDF builder: the winding-number pass, and the checks that decide whether the
/// pseudonormal sign can be trusted on a closed mesh. Internal header of the SDF builder.
///
/// @details The pseudonormal sign is exact on a closed, consistently oriented mesh that does not intersect
/// itself. A closed mesh can still intersect itself (two overlapping cubes exported as one mesh) or hold
/// nested shells of the same orientation; there a node's closest feature may be a face buried inside the
/// solid and the pseudonormal says "outside" (about a quarter of the inside nodes of two overlapping cubes).
/// The generalized winding number is right on such meshes (>= 1 inside the union). So the automatic choice
/// checks the mesh first: any strictly crossing pair of triangles, or any block of nodes away from the surface
/// whose pseudonormal sign disagrees with the winding number at its centre, switches the build to the
/// winding number.
#pragma once

#include <cstddef>
#include <vector>

#include "sdf_build_blocks.h"
#include "sdfccd/mesh/sdf_builder.h"
#include "triangle_bvh.h"
#include "winding_number.h"

namespace sdfccd::detail {

/// The number of pairs of triangles that share no vertex and cross: an edge of one passes strictly through
/// the interior of the other (touching and coplanar contact are not counted). Parallel over triangles.
std::size_t countSelfIntersections(const TriangleMesh& mesh, const TriangleBvh& bvh, int threads);

/// Over the blocks whose bounding ball holds no surface (where the sign is constant) and whose centre's
/// winding number is clearly 0 or 1 (|w - 1/2| > 1/4): the number of nodes whose sign in `values` disagrees
/// with it. One winding number per such block.
std::size_t countSignsDisagreeingWithWinding(const TriangleBvh& bvh, const FastWindingNumber& winding,
                                             const SdfGridLayout& layout, const std::vector<Block>& blocks, int threads,
                                             const float* values);

/// Negates `values` (unsigned distances) where the winding number is >= `threshold`; a block whose ball holds
/// no surface and whose centre is clearly inside or outside gives its sign to all its nodes.
void signByWindingNumber(const TriangleBvh& bvh, const FastWindingNumber& winding, double threshold,
                         const SdfGridLayout& layout, const std::vector<Block>& blocks, int threads,
                         ProgressReporter& progress, float* values);

}  // namespace sdfccd::detail
