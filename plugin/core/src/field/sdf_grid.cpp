/// @file
/// @brief SdfGrid: validation and trilinear interpolation.
#include "sdfccd/field/sdf_grid.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sdfccd/error.h"
#include "sdfccd/field/trilinear.h"

namespace sdfccd {

namespace {

// Queries compute (p - origin) / spacing, squared distances to the box and octree bounds in double: a box
// whose corners or extent come near the double range (spacing 1e308 gives an infinite box) or a spacing so
// small that its inverse overflows would answer with infinities and NaNs, so such grids are refused.
constexpr double kMaxBoxCoordinate = 1e100;
constexpr double kMinSpacing = 1e-100;

void checkBoxIsUsable(const Vec3i& nodeCounts, const Vec3& origin, double spacing) {
  if (spacing < kMinSpacing) {
    std::ostringstream s;
    s << "grid spacing " << spacing << " is below " << kMinSpacing;
    throw Error(s.str());
  }
  const Vec3 farCorner = origin + spacing * (nodeCounts - Vec3i::Ones()).cast<double>();
  if (!farCorner.allFinite() || farCorner.cwiseAbs().maxCoeff() > kMaxBoxCoordinate ||
      origin.cwiseAbs().maxCoeff() > kMaxBoxCoordinate) {
    std::ostringstream s;
    s << "grid box (origin " << origin.x() << " " << origin.y() << " " << origin.z() << ", spacing " << spacing << ", "
      << nodeCounts.x() << " x " << nodeCounts.y() << " x " << nodeCounts.z()
      << " nodes) is not finite or reaches past +-" << kMaxBoxCoordinate;
    throw Error(s.str());
  }
}

}  // namespace

SdfGrid::SdfGrid(const Vec3i& nodeCounts, const Vec3& origin, double spacing, std::vector<float> values)
    : m_nodeCounts(nodeCounts), m_origin(origin), m_spacing(spacing), m_values(std::move(values)) {
  if ((nodeCounts.array() < 2).any()) {
    std::ostringstream s;
    s << "grid needs at least 2 nodes along each axis, got " << nodeCounts.x() << " x " << nodeCounts.y() << " x "
      << nodeCounts.z();
    throw Error(s.str());
  }
  const double count = static_cast<double>(nodeCounts.x()) * nodeCounts.y() * nodeCounts.z();
  if (count != static_cast<double>(m_values.size())) {
    std::ostringstream s;
    s << "grid of " << nodeCounts.x() << " x " << nodeCounts.y() << " x " << nodeCounts.z() << " nodes needs "
      << static_cast<long long>(count) << " values, got " << m_values.size();
    throw Error(s.str());
  }
  if (!std::isfinite(spacing) || spacing <= 0.0) {
    throw Error("grid spacing must be finite and positive, got " + std::to_string(spacing));
  }
  if (!origin.allFinite()) throw Error("grid origin is not finite");
  checkBoxIsUsable(nodeCounts, origin, spacing);
  const auto [lo, hi] = std::minmax_element(m_values.begin(), m_values.end());
  for (std::size_t n = 0; n < m_values.size(); ++n) {
    if (!std::isfinite(m_values[n])) throw Error("grid value " + std::to_string(n) + " is not finite");
  }
  m_minValue = *lo;
  m_maxValue = *hi;
}

bool SdfGrid::contains(const Vec3& pointInSdf) const {
  const Box3 b = box();
  return (pointInSdf.array() >= b.min().array()).all() && (pointInSdf.array() <= b.max().array()).all();
}

void SdfGrid::locate(const Vec3& pointInSdf, Vec3i& outCell, Vec3& outLocal) const {
  const Vec3 u = (pointInSdf - m_origin) / m_spacing;
  for (int a = 0; a < 3; ++a) {
    const int last = m_nodeCounts[a] - 2;
    double f = std::floor(u[a]);
    // NaN compares false both ways and lands in cell 0 with local 0: callers validate inputs first.
    int c = f < 0.0 ? 0 : (f > last ? last : static_cast<int>(f));
    outCell[a] = c;
    outLocal[a] = std::clamp(u[a] - c, 0.0, 1.0);
  }
}

void SdfGrid::cellCorners(const Vec3i& cell, double outCorners[8]) const {
  const std::size_t base = index(cell.x(), cell.y(), cell.z());
  const std::size_t dy = static_cast<std::size_t>(m_nodeCounts.x());
  const std::size_t dz = dy * static_cast<std::size_t>(m_nodeCounts.y());
  outCorners[0] = m_values[base];
  outCorners[1] = m_values[base + 1];
  outCorners[2] = m_values[base + dy];
  outCorners[3] = m_values[base + dy + 1];
  outCorners[4] = m_values[base + dz];
  outCorners[5] = m_values[base + dz + 1];
  outCorners[6] = m_values[base + dz + dy];
  outCorners[7] = m_values[base + dz + dy + 1];
}

double SdfGrid::interpolate(const Vec3& pointInSdf) const {
  Vec3 g;
  return interpolate(pointInSdf, g);
}

Vec3 SdfGrid::gradient(const Vec3& pointInSdf) const {
  Vec3 g;
  interpolate(pointInSdf, g);
  return g;
}

double SdfGrid::interpolate(const Vec3& pointInSdf, Vec3& outGradient) const {
  Vec3i cell;
  Vec3 w;
  locate(pointInSdf, cell, w);
  double c[8];
  cellCorners(cell, c);
  const double x = w.x(), y = w.y(), z = w.z();
  // Interpolate along x, then y, then z; the gradient follows from the same partial sums.
  const TrilinearSums s = trilinearSums(c, x, y);
  const double c00 = s.c00, c10 = s.c10, c01 = s.c01, c11 = s.c11, c0 = s.c0, c1 = s.c1;
  const double dx0 = (c[1] - c[0]) + y * ((c[3] - c[2]) - (c[1] - c[0]));
  const double dx1 = (c[5] - c[4]) + y * ((c[7] - c[6]) - (c[5] - c[4]));
  outGradient.x() = (dx0 + z * (dx1 - dx0)) / m_spacing;
  outGradient.y() = ((c10 - c00) + z * ((c11 - c01) - (c10 - c00))) / m_spacing;
  outGradient.z() = (c1 - c0) / m_spacing;
  return c0 + z * (c1 - c0);
}

}  // namespace sdfccd
