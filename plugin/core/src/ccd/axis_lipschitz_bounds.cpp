/// @file
/// @brief AxisLipschitzBounds (see axis_lipschitz_bounds.h).
#include "sdfccd/ccd/axis_lipschitz_bounds.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <unordered_map>

#include "sdfccd/error.h"
#include "sdfccd/field/cell_gradient_bound.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/tolerances.h"

namespace sdfccd {
namespace {

/// `v` rounded up to a float.
float roundedUpToFloat(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

}  // namespace

AxisLipschitzBounds::AxisLipschitzBounds(const SdfGrid& grid, int blockCells) {
  if (blockCells < 1) throw Error("axis Lipschitz bounds: blockCells must be >= 1");
  if (grid.empty()) throw Error("axis Lipschitz bounds: empty grid");
  const Vec3i cells = grid.cellCounts();
  for (int a = 0; a < 3; ++a) m_blocks[a] = (cells[a] + blockCells - 1) / blockCells;
  m_box = grid.box();
  m_origin = grid.origin();
  m_blockCells = blockCells;
  m_blockSize = blockCells * grid.spacing();
  m_reach = m_blockSize * (1.0 - tolerance::kBlockReachShrink);  // a hair less, for the rounding of blockOf
  const auto blockIndex = [&](int bx, int by, int bz) {
    return static_cast<std::size_t>(bx) +
           static_cast<std::size_t>(m_blocks.x()) *
               (static_cast<std::size_t>(by) + static_cast<std::size_t>(m_blocks.y()) * static_cast<std::size_t>(bz));
  };
  std::vector<std::array<double, 3>> own(static_cast<std::size_t>(m_blocks.prod()), {0.0, 0.0, 0.0});
  for (int k = 0; k < cells.z(); ++k) {
    for (int j = 0; j < cells.y(); ++j) {
      const std::size_t rowBlock = blockIndex(0, j / blockCells, k / blockCells);
      for (int i = 0; i < cells.x(); ++i) {
        std::array<double, 3>& b = own[rowBlock + static_cast<std::size_t>(i / blockCells)];
        const std::array<double, 3> c = cellAxisBounds(grid, i, j, k);
        for (int a = 0; a < 3; ++a) b[a] = std::max(b[a], c[a]);
      }
    }
  }
  // The 3x3x3 neighbourhood maximum per axis, in value units per model unit, grown for the rounding of the
  // interpolation itself (as the whole grid's bound is, field_culling_bounds.cpp) and rounded up.
  const double scale = tolerance::kBoundGrowth / grid.spacing();
  m_bounds.assign(own.size(), Block{});
  for (int bz = 0; bz < m_blocks.z(); ++bz) {
    for (int by = 0; by < m_blocks.y(); ++by) {
      for (int bx = 0; bx < m_blocks.x(); ++bx) {
        std::array<double, 3> worst{0.0, 0.0, 0.0};
        for (int dz = std::max(0, bz - 1); dz <= std::min(m_blocks.z() - 1, bz + 1); ++dz)
          for (int dy = std::max(0, by - 1); dy <= std::min(m_blocks.y() - 1, by + 1); ++dy)
            for (int dx = std::max(0, bx - 1); dx <= std::min(m_blocks.x() - 1, bx + 1); ++dx)
              for (int a = 0; a < 3; ++a) worst[a] = std::max(worst[a], own[blockIndex(dx, dy, dz)][a]);
        Block& b = m_bounds[blockIndex(bx, by, bz)];
        b.x = roundedUpToFloat(worst[0] * scale);
        b.y = roundedUpToFloat(worst[1] * scale);
        b.z = roundedUpToFloat(worst[2] * scale);
        const double norm =
            std::sqrt(static_cast<double>(b.x) * b.x + static_cast<double>(b.y) * b.y + static_cast<double>(b.z) * b.z);
        b.norm = roundedUpToFloat(norm * tolerance::kBoundGrowth);
      }
    }
  }
}

int AxisLipschitzBounds::defaultBlockCells(const SdfGrid& grid) {
  const Vec3i cells = grid.cellCounts();
  int b = 2;
  const auto count = [&](int blockCells) {
    double n = 1.0;
    for (int a = 0; a < 3; ++a) n *= static_cast<double>((cells[a] + blockCells - 1) / blockCells);
    return n;
  };
  while (count(b) > double(1 << 18)) b *= 2;
  return b;
}

int AxisLipschitzBounds::blockOf(const Vec3& pointInSdf) const {
  if (!m_box.contains(pointInSdf)) return -1;
  Vec3i b;
  for (int a = 0; a < 3; ++a) {
    const double u = std::floor((pointInSdf[a] - m_origin[a]) / m_blockSize);
    b[a] = static_cast<int>(std::clamp(u, 0.0, static_cast<double>(m_blocks[a] - 1)));
  }
  return b.x() + m_blocks.x() * (b.y() + m_blocks.y() * b.z());
}

std::shared_ptr<const AxisLipschitzBounds> sharedAxisLipschitzBounds(const GridField& field) {
  // Weak entries keyed by the field's instance id (never reused): the bounds go with their last holder.
  static std::mutex mutex;
  static std::unordered_map<std::uint64_t, std::weak_ptr<const AxisLipschitzBounds>> registry;
  const std::lock_guard<std::mutex> lock(mutex);
  std::weak_ptr<const AxisLipschitzBounds>& slot = registry[field.instanceId()];
  if (std::shared_ptr<const AxisLipschitzBounds> shared = slot.lock()) return shared;
  auto bounds =
      std::make_shared<const AxisLipschitzBounds>(field.grid(), AxisLipschitzBounds::defaultBlockCells(field.grid()));
  slot = bounds;
  if (registry.size() > 64) {  // forget the fields nobody holds any more
    for (auto it = registry.begin(); it != registry.end();) it = it->second.expired() ? registry.erase(it) : ++it;
  }
  return bounds;
}

}  // namespace sdfccd
