/// @file
/// @brief LocalLipschitzBounds (see local_lipschitz_bounds.h).
#include "sdfccd/haptics/local_lipschitz_bounds.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sdfccd/error.h"
#include "sdfccd/field/cell_gradient_bound.h"
#include "sdfccd/tolerances.h"

namespace sdfccd::haptics {

LocalLipschitzBounds::LocalLipschitzBounds(const SdfGrid& grid, int blockCells) {
  if (blockCells < 1) throw Error("local Lipschitz bounds: blockCells must be >= 1");
  if (grid.empty()) throw Error("local Lipschitz bounds: empty grid");
  const Vec3i cells = grid.cellCounts();
  for (int a = 0; a < 3; ++a) m_blocks[a] = (cells[a] + blockCells - 1) / blockCells;
  m_origin = grid.origin();
  m_blockSize = blockCells * grid.spacing();
  m_reach = m_blockSize * (1.0 - tolerance::kBlockReachShrink);  // a hair less, for the rounding of the block lookup
  const auto blockIndex = [&](int bx, int by, int bz) {
    return static_cast<std::size_t>(bx) +
           static_cast<std::size_t>(m_blocks.x()) *
               (static_cast<std::size_t>(by) + static_cast<std::size_t>(m_blocks.y()) * static_cast<std::size_t>(bz));
  };
  // Per block: the largest per-cell bound (squared, in value units per cell).
  std::vector<double> own(static_cast<std::size_t>(m_blocks.prod()), 0.0);
  for (int k = 0; k < cells.z(); ++k) {
    for (int j = 0; j < cells.y(); ++j) {
      const std::size_t rowBlock = blockIndex(0, j / blockCells, k / blockCells);
      for (int i = 0; i < cells.x(); ++i) {
        double& b = own[rowBlock + static_cast<std::size_t>(i / blockCells)];
        b = std::max(b, cellGradientBoundSquared(grid, i, j, k));
      }
    }
  }
  // The 3x3x3 neighbourhood maximum, converted to a gradient bound and rounded up (with slack for the rounding
  // of the interpolation itself).
  m_bounds.assign(own.size(), 0.0f);
  for (int bz = 0; bz < m_blocks.z(); ++bz) {
    for (int by = 0; by < m_blocks.y(); ++by) {
      for (int bx = 0; bx < m_blocks.x(); ++bx) {
        double worst = 0.0;
        for (int dz = std::max(0, bz - 1); dz <= std::min(m_blocks.z() - 1, bz + 1); ++dz)
          for (int dy = std::max(0, by - 1); dy <= std::min(m_blocks.y() - 1, by + 1); ++dy)
            for (int dx = std::max(0, bx - 1); dx <= std::min(m_blocks.x() - 1, bx + 1); ++dx)
              worst = std::max(worst, own[blockIndex(dx, dy, dz)]);
        const double bound = std::sqrt(worst) / grid.spacing() * tolerance::kBoundGrowth;
        float f = static_cast<float>(bound);
        if (static_cast<double>(f) < bound) f = std::nextafter(f, std::numeric_limits<float>::infinity());
        m_bounds[blockIndex(bx, by, bz)] = f;
      }
    }
  }
}

double LocalLipschitzBounds::lipschitzNear(const Vec3& pointInSdf) const {
  Vec3i b;
  for (int a = 0; a < 3; ++a) {
    const double u = std::floor((pointInSdf[a] - m_origin[a]) / m_blockSize);
    b[a] = static_cast<int>(std::clamp(u, 0.0, static_cast<double>(m_blocks[a] - 1)));
  }
  return static_cast<double>(m_bounds[static_cast<std::size_t>(b.x()) +
                                      static_cast<std::size_t>(m_blocks.x()) *
                                          (static_cast<std::size_t>(b.y()) +
                                           static_cast<std::size_t>(m_blocks.y()) * static_cast<std::size_t>(b.z()))]);
}

}  // namespace sdfccd::haptics
