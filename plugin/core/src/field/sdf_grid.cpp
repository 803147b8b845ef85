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
  m_boxMax = m_origin + m_spacing * cellCounts().cast<double>();
}

}  // namespace sdfccd
