/// @file
/// @brief The nested point tree build (see point_tree.h; paper Section 3.3, Barbic and James).
#include "sdfccd/shell/point_tree.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sdfccd/error.h"

namespace sdfccd {

PointTree::PointTree(PointShell shell, const PointTreeSettings& settings) : m_shell(std::move(shell)) {
  if (m_shell.empty()) throw Error("PointTree: the shell has no points");
  m_shell.validate();
  if (settings.branching < 2 || settings.branching > 64) throw Error("PointTree: branching must be in [2, 64]");
  if (settings.refinements < 0 || settings.refinements > 100) throw Error("PointTree: refinements must be in [0, 100]");
  if (m_shell.size() > static_cast<std::size_t>(1) << 30) throw Error("PointTree: too many points");

  m_curvature = shellCurvatures(m_shell);
  const int count = static_cast<int>(m_shell.size());
  const auto& x = m_shell.positions;
  std::vector<int> perm(count);
  for (int n = 0; n < count; ++n) perm[n] = n;
  std::vector<int> rangeBegin;
  std::vector<int> rangeEnd;
  std::vector<int> depth;
  const auto reserve = static_cast<std::size_t>(count) * 2;
  m_nodePoint.reserve(reserve);
  rangeBegin.reserve(reserve);
  rangeEnd.reserve(reserve);
  depth.reserve(reserve);

  // Root: the point nearest the centroid.
  Vec3 centroid = Vec3::Zero();
  for (const auto& p : x) centroid += p;
  centroid /= count;
  int root = 0;
  for (int n = 1; n < count; ++n) {
    if ((x[n] - centroid).squaredNorm() < (x[root] - centroid).squaredNorm()) root = n;
  }
  m_nodePoint.push_back(root);
  rangeBegin.push_back(0);
  rangeEnd.push_back(count);
  depth.push_back(0);

  std::vector<double> minDistSq(count);  // by position in perm
  std::vector<int> label(count);         // by position in perm
  std::vector<int> scratch(count);
  std::vector<int> seeds;
  std::vector<int> clusterSize;
  std::vector<Vec3> clusterSum;

  // Nodes are processed in the order they are created: breadth first.
  for (std::size_t node = 0; node < m_nodePoint.size(); ++node) {
    const int begin = rangeBegin[node];
    const int end = rangeEnd[node];
    const int rep = m_nodePoint[node];
    const int size = end - begin;
    const Vec3 c = x[rep];
    double maxSq = 0.0;
    for (int i = begin; i < end; ++i) {
      minDistSq[i] = (x[perm[i]] - c).squaredNorm();
      maxSq = std::max(maxSq, minDistSq[i]);
    }
    m_center.push_back(c);
    m_radius.push_back(std::sqrt(maxSq));
    if (size == 1) {
      m_firstChild.push_back(-1);
      m_childCount.push_back(0);
      continue;
    }
    // Farthest-point seeds, the node's own point first. Seeds are marked with a negative distance.
    const int k = std::min(settings.branching, size);
    seeds.assign(1, rep);
    for (int i = begin; i < end; ++i) {
      if (perm[i] == rep) minDistSq[i] = -1.0;
    }
    while (static_cast<int>(seeds.size()) < k) {
      int best = -1;
      for (int i = begin; i < end; ++i) {
        if (minDistSq[i] < 0.0) continue;
        if (best < 0 || minDistSq[i] > minDistSq[best]) best = i;
      }
      const int s = perm[best];
      seeds.push_back(s);
      minDistSq[best] = -1.0;
      for (int i = begin; i < end; ++i) {
        if (minDistSq[i] > 0.0) minDistSq[i] = std::min(minDistSq[i], (x[perm[i]] - x[s]).squaredNorm());
      }
    }
    // Nearest-seed assignment with medoid refinements (the first seed stays the node's point).
    auto assign = [&]() {
      for (int i = begin; i < end; ++i) {
        const Vec3& p = x[perm[i]];
        int bestSeed = 0;
        double bestSq = (p - x[seeds[0]]).squaredNorm();
        for (int s = 1; s < k; ++s) {
          const double dSq = (p - x[seeds[s]]).squaredNorm();
          if (dSq < bestSq) {
            bestSq = dSq;
            bestSeed = s;
          }
        }
        label[i] = bestSeed;
      }
      // A seed always belongs to its own cluster (coincident points could tie), so no cluster is empty and
      // every cluster is smaller than the node.
      for (int i = begin; i < end; ++i) {
        for (int s = 0; s < k; ++s) {
          if (perm[i] == seeds[s]) label[i] = s;
        }
      }
    };
    assign();
    for (int r = 0; r < settings.refinements; ++r) {
      clusterSum.assign(k, Vec3::Zero());
      clusterSize.assign(k, 0);
      for (int i = begin; i < end; ++i) {
        clusterSum[label[i]] += x[perm[i]];
        ++clusterSize[label[i]];
      }
      std::vector<double> bestSq(k, std::numeric_limits<double>::infinity());
      std::vector<int> medoid(seeds);
      for (int i = begin; i < end; ++i) {
        const int s = label[i];
        if (s == 0) continue;
        const double dSq = (x[perm[i]] - clusterSum[s] / clusterSize[s]).squaredNorm();
        if (dSq < bestSq[s]) {
          bestSq[s] = dSq;
          medoid[s] = perm[i];
        }
      }
      if (medoid == seeds) break;
      seeds = medoid;
      assign();
    }
    // Partition the range by cluster (stable counting sort) and create the children.
    clusterSize.assign(k + 1, 0);
    for (int i = begin; i < end; ++i) ++clusterSize[label[i] + 1];
    for (int s = 0; s < k; ++s) clusterSize[s + 1] += clusterSize[s];
    std::vector<int> offset(clusterSize.begin(), clusterSize.end() - 1);
    for (int i = begin; i < end; ++i) scratch[begin + offset[label[i]]++] = perm[i];
    std::copy(scratch.begin() + begin, scratch.begin() + end, perm.begin() + begin);
    m_firstChild.push_back(static_cast<int>(m_nodePoint.size()));
    m_childCount.push_back(k);
    for (int s = 0; s < k; ++s) {
      m_nodePoint.push_back(seeds[s]);
      rangeBegin.push_back(begin + clusterSize[s]);
      rangeEnd.push_back(begin + clusterSize[s + 1]);
      depth.push_back(depth[node] + 1);
    }
  }

  m_levelBegin.clear();
  for (int n = 0; n < nodeCount(); ++n) {
    if (n == 0 || depth[n] != depth[n - 1]) m_levelBegin.push_back(n);
  }
  m_levelBegin.push_back(nodeCount());
  m_leafOfPoint.assign(count, -1);
  for (int n = 0; n < nodeCount(); ++n) {
    if (m_childCount[n] == 0) m_leafOfPoint[m_nodePoint[n]] = n;
  }
}

void PointTree::pointsUnder(int node, std::vector<int>& out) const {
  std::vector<int> stack{node};
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    if (m_childCount[n] == 0) {
      out.push_back(m_nodePoint[n]);
      continue;
    }
    for (int c = 0; c < m_childCount[n]; ++c) stack.push_back(m_firstChild[n] + c);
  }
}

}  // namespace sdfccd
