/// @file
/// @brief The blocks of nodes the SDF builder's passes work on, the node index and the progress reporter.
/// Internal header of the SDF builder (sdf_builder.cpp, sdf_distance_pass.cpp, sdf_sign.cpp).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <mutex>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/progress.h"

namespace sdfccd::detail {

constexpr int kBlock = 8;  // nodes per block side (a parallel task)

/// A box of nodes [begin, end).
struct Block {
  Vec3i begin;  // first node
  Vec3i end;    // one past the last node
};

/// Index of node (i, j, k) in a grid of `n` nodes, i fastest.
inline std::size_t nodeIndex(const Vec3i& n, int i, int j, int k) {
  return static_cast<std::size_t>(i) +
         static_cast<std::size_t>(n.x()) *
             (static_cast<std::size_t>(j) + static_cast<std::size_t>(n.y()) * static_cast<std::size_t>(k));
}

/// The grid cut into blocks of up to kBlock^3 nodes.
inline std::vector<Block> makeBlocks(const Vec3i& nodes) {
  std::vector<Block> blocks;
  for (int k = 0; k < nodes.z(); k += kBlock)
    for (int j = 0; j < nodes.y(); j += kBlock)
      for (int i = 0; i < nodes.x(); i += kBlock) {
        const Vec3i begin(i, j, k);
        blocks.push_back({begin, (begin + Vec3i::Constant(kBlock)).cwiseMin(nodes)});
      }
  return blocks;
}

// Calls `progress` (never concurrently, at most every 1/200 of the work) from whichever thread gets there.
class ProgressReporter {
 public:
  ProgressReporter(const ProgressCallback& progress, std::size_t total, double begin, double end)
      : m_progress(progress), m_total(std::max<std::size_t>(total, 1)), m_begin(begin), m_end(end) {}
  void advance() {
    const std::size_t done = ++m_done;
    if (!m_progress || (done * 200 / m_total == (done - 1) * 200 / m_total && done != m_total)) return;
    std::unique_lock<std::mutex> lock(m_mutex, std::try_to_lock);
    if (!lock.owns_lock()) return;
    // Read the count again under the lock, so reported fractions never decrease.
    const double fraction =
        m_begin + (m_end - m_begin) * static_cast<double>(m_done.load()) / static_cast<double>(m_total);
    if (fraction <= m_last) return;
    m_last = fraction;
    m_progress(fraction);
  }

 private:
  const ProgressCallback& m_progress;
  std::size_t m_total;
  double m_begin, m_end;
  std::atomic<std::size_t> m_done{0};
  std::mutex m_mutex;
  double m_last = -1.0;
};

}  // namespace sdfccd::detail
