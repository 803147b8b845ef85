/// @file
/// @brief The OpenVDB peer of `sdfccd bench segments`: LevelSetRayIntersector on the same field.
///
/// @details Built only when OpenVDB is found (target sdfccd_openvdb_peer, define SDFCCD_HAS_OPENVDB on the
/// tool). The grid is copied into a narrow-band level set (|phi| < 3 cells, signed flood fill inside) with
/// the same node positions; each segment becomes a world-space ray from p0 towards p1 limited to the
/// segment's length, and the first zero crossing found by OpenVDB is compared with ours.
#pragma once

#include <string>
#include <vector>

#include "sdfccd/field/sdf_grid.h"
#include "sdfccd/math_types.h"

namespace sdfccd::cli {

/// One segment and our exact first hit (fraction, < 0 when none).
struct PeerSegment {
  Vec3 p0, p1;
  double exactFraction = -1.0;
};

/// What the peer measured.
struct OpenVdbPeerResult {
  double conversionSeconds = 0.0;  ///< dense grid -> narrow-band VDB level set (s)
  double microseconds = 0.0;       ///< per segment, thread CPU time
  long long segments = 0;          ///< segments compared
  long long exactHits = 0;         ///< our first hits
  long long peerHits = 0;          ///< OpenVDB's first hits
  long long missed = 0;            ///< we hit, OpenVDB does not
  long long misplaced = 0;         ///< both hit, more than 1% of a cell apart
  long long spurious = 0;          ///< OpenVDB hits, we do not
  std::size_t vdbBytes = 0;        ///< memory of the VDB grid
  double meanAbsPhiPeer = 0.0;     ///< mean |phi| / spacing of the trilinear field at OpenVDB's hits
  double meanAbsPhiOurs = 0.0;     ///< the same at ours (same segments, both hit)
};

/// Runs the peer on `segments` (all must start outside the level set, phi(p0) > 0).
OpenVdbPeerResult runOpenVdbPeer(const SdfGrid& grid, const std::vector<PeerSegment>& segments);

}  // namespace sdfccd::cli
