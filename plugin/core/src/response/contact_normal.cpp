/// @file
/// @brief shellCurvatures (contact_normal.h): neighbours found with a hash grid of cells one search radius wide.
#include "sdfccd/response/contact_normal.h"

#include <cstdint>
#include <limits>
#include <unordered_map>

namespace sdfccd {
namespace {

struct NeighbourCell {
  std::int64_t x, y, z;
  bool operator==(const NeighbourCell& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct NeighbourCellHash {
  std::size_t operator()(const NeighbourCell& k) const {
    return std::size_t(k.x * 73856093) ^ std::size_t(k.y * 19349663) ^ std::size_t(k.z * 83492791);
  }
};

class NeighbourGrid {
 public:
  NeighbourGrid(const std::vector<Vec3>& points, double cell) : m_points(points), m_cell(cell) {
    for (std::size_t i = 0; i < points.size(); ++i) m_cells[key(points[i])].push_back(static_cast<int>(i));
  }
  /// Calls f(j) for every point j within the 27 cells around p (a superset of those within one cell width).
  template <class F>
  void forNear(const Vec3& p, F&& f) const {
    const NeighbourCell c = key(p);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = m_cells.find(NeighbourCell{c.x + dx, c.y + dy, c.z + dz});
          if (it == m_cells.end()) continue;
          for (int j : it->second) f(j);
        }
  }

 private:
  NeighbourCell key(const Vec3& p) const {
    return NeighbourCell{static_cast<std::int64_t>(std::floor(p.x() / m_cell)),
                   static_cast<std::int64_t>(std::floor(p.y() / m_cell)),
                   static_cast<std::int64_t>(std::floor(p.z() / m_cell))};
  }
  const std::vector<Vec3>& m_points;
  double m_cell;
  std::unordered_map<NeighbourCell, std::vector<int>, NeighbourCellHash> m_cells;
};

/// The typical point spacing: from the mean area per point when known, else from the bounding box's surface.
double typicalPointSpacing(const PointShell& shell) {
  if (shell.hasAreas()) {
    const double perPoint = shell.totalArea() / double(shell.size());
    if (perPoint > 0.0 && std::isfinite(perPoint)) return std::sqrt(perPoint);
  }
  Vec3 lo = shell.positions[0], hi = shell.positions[0];
  for (const Vec3& p : shell.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Vec3 e = hi - lo;
  const double boxArea = 2.0 * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
  return std::sqrt(std::max(boxArea, 1e-300) / double(shell.size()));
}

}  // namespace

std::vector<double> shellCurvatures(const PointShell& shell) {
  std::vector<double> curvature(shell.size(), 0.0);
  if (shell.size() < 2) return curvature;
  const double radius = 1.5 * typicalPointSpacing(shell);
  if (!(radius > 0.0) || !std::isfinite(radius)) return curvature;
  const NeighbourGrid grid(shell.positions, radius);
  const double radiusSquared = radius * radius;
  for (std::size_t i = 0; i < shell.size(); ++i) {
    const Vec3& p = shell.positions[i];
    const Vec3& n = shell.normals[i];
    double largest = 0.0;
    grid.forNear(p, [&](int j) {
      if (static_cast<std::size_t>(j) == i) return;
      const double squared = (shell.positions[static_cast<std::size_t>(j)] - p).squaredNorm();
      if (!(squared > 0.0) || squared > radiusSquared) return;
      largest = std::max(largest, angleBetween(n, shell.normals[static_cast<std::size_t>(j)]) / std::sqrt(squared));
    });
    curvature[i] = largest;
  }
  return curvature;
}

}  // namespace sdfccd
