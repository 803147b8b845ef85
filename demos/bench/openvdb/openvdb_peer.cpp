/// @file
/// @brief OpenVDB's LevelSetRayIntersector as the peer of the segment CCD benchmark (see openvdb_peer.h).
#include "bench/openvdb_peer.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/RayIntersector.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <chrono>
#include <cmath>

#include "sdfccd/thread_cpu_time.h"

namespace sdfccd::cli {

OpenVdbPeerResult runOpenVdbPeer(const SdfGrid& grid, const std::vector<PeerSegment>& segments) {
  openvdb::initialize();
  OpenVdbPeerResult result;
  const double h = grid.spacing();
  const float background = static_cast<float>(3.0 * h);
  const auto start = std::chrono::steady_clock::now();
  openvdb::FloatGrid::Ptr vdb = openvdb::FloatGrid::create(background);
  // Voxel (i, j, k) at origin + h (i, j, k): the same node positions as ours.
  openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(h);
  transform->postTranslate(openvdb::Vec3d(grid.origin().x(), grid.origin().y(), grid.origin().z()));
  vdb->setTransform(transform);
  vdb->setGridClass(openvdb::GRID_LEVEL_SET);
  {
    auto accessor = vdb->getAccessor();
    const Vec3i n = grid.nodeCounts();
    for (int k = 0; k < n.z(); ++k)
      for (int j = 0; j < n.y(); ++j)
        for (int i = 0; i < n.x(); ++i) {
          const float v = grid.value(i, j, k);
          if (std::abs(v) < background) accessor.setValue(openvdb::Coord(i, j, k), v);
        }
  }
  openvdb::tools::signedFloodFill(vdb->tree());
  result.conversionSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.vdbBytes = vdb->memUsage();

  openvdb::tools::LevelSetRayIntersector<openvdb::FloatGrid> intersector(*vdb);
  std::vector<double> peer(segments.size(), -1.0);
  const double cpuStart = threadCpuSeconds();
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const Vec3 d = segments[s].p1 - segments[s].p0;
    const double length = d.norm();
    if (length == 0.0) continue;
    const Vec3 dir = d / length;
    openvdb::math::Ray<double> ray(openvdb::Vec3d(segments[s].p0.x(), segments[s].p0.y(), segments[s].p0.z()),
                                   openvdb::Vec3d(dir.x(), dir.y(), dir.z()), 0.0, length);
    openvdb::Vec3d xyz;
    double t = 0.0;
    if (intersector.intersectsWS(ray, xyz, t)) peer[s] = t / length;
  }
  result.microseconds =
      1e6 * (threadCpuSeconds() - cpuStart) / static_cast<double>(std::max<std::size_t>(segments.size(), 1));

  result.segments = static_cast<long long>(segments.size());
  long long both = 0;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const bool ours = segments[s].exactFraction >= 0.0, theirs = peer[s] >= 0.0;
    result.exactHits += ours;
    result.peerHits += theirs;
    if (ours && !theirs) ++result.missed;
    if (!ours && theirs) ++result.spurious;
    if (ours && theirs) {
      const double length = (segments[s].p1 - segments[s].p0).norm();
      if (std::abs(peer[s] - segments[s].exactFraction) * length > 0.01 * h) ++result.misplaced;
      const Vec3 d = segments[s].p1 - segments[s].p0;
      result.meanAbsPhiPeer += std::abs(grid.interpolate(segments[s].p0 + peer[s] * d)) / h;
      result.meanAbsPhiOurs += std::abs(grid.interpolate(segments[s].p0 + segments[s].exactFraction * d)) / h;
      ++both;
    }
  }
  if (both > 0) {
    result.meanAbsPhiPeer /= static_cast<double>(both);
    result.meanAbsPhiOurs /= static_cast<double>(both);
  }
  return result;
}

}  // namespace sdfccd::cli
