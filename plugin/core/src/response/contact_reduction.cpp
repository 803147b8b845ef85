/// @file
/// @brief Normal clustering and 4-point area reduction with hysteresis (see contact_reduction.h;
/// docs/design/contact-response.md, solver mode).
#include "sdfccd/response/contact_reduction.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/tolerances.h"

namespace sdfccd {
namespace {

// Values this close (relative) count as equal, so that symmetric layouts break ties by point id, not by rounding.
constexpr double kTieSlack = 1e-12;

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

double triangleArea(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return 0.5 * std::abs(cross2(b - a, c - a));
}

// |shoelace| of the polygon a, b, c, d.
double quadArea(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                const Eigen::Vector2d& d) {
  return 0.5 * std::abs(cross2(a, b) + cross2(b, c) + cross2(c, d) + cross2(d, a));
}

// Area of the convex hull of four points: the hull is one of the 4 triangles or one of the 3 cyclic quads,
// and every other candidate (a triangle inside it, a self-intersecting quad) has less area.
double hullArea(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                const Eigen::Vector2d& d) {
  return std::max({triangleArea(a, b, c), triangleArea(a, b, d), triangleArea(a, c, d), triangleArea(b, c, d),
                   quadArea(a, b, c, d), quadArea(a, b, d, c), quadArea(a, c, b, d)});
}

// True if (valueA, idA) beats (valueB, idB): the larger value, near-equal values by the smaller id.
bool beats(double valueA, int idA, double valueB, int idB) {
  const double slack = kTieSlack * std::max(std::abs(valueA), std::abs(valueB));
  if (valueA > valueB + slack) return true;
  if (valueB > valueA + slack) return false;
  return idA < idB;
}

// Unit vectors u, v with (u, v, n) orthonormal.
void planeBasis(const Vec3& n, Vec3& u, Vec3& v) {
  const Vec3 helper = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  u = n.cross(helper).normalized();
  v = n.cross(u);
}

class ClusterSelector {
 public:
  ClusterSelector(const std::vector<ContactCandidate>& candidates, const std::vector<int>& members, const Vec3& normal,
                  const std::vector<SelectedContactPoint>& previous, double hysteresis)
      : m_candidates(candidates), m_members(members), m_previous(previous), m_hysteresis(hysteresis) {
    Vec3 u;
    Vec3 v;
    planeBasis(normal, u, v);
    m_inPlane.reserve(members.size());
    for (int m : members) m_inPlane.emplace_back(candidates[m].position.dot(u), candidates[m].position.dot(v));
  }

  // Picks the member (local index) that maximizes value(local), skipping those already taken; with hysteresis.
  template <class Value>
  int pick(const std::array<int, kMaxPointsPerCluster>& taken, int takenCount, Value value) const {
    auto isTaken = [&](int local) {
      return std::find(taken.begin(), taken.begin() + takenCount, local) != taken.begin() + takenCount;
    };
    int best = -1;
    double bestValue = 0.0;
    for (int local = 0; local < static_cast<int>(m_members.size()); ++local) {
      if (isTaken(local)) continue;
      const double x = value(local);
      if (best < 0 || beats(x, id(local), bestValue, id(best))) {
        best = local;
        bestValue = x;
      }
    }
    if (m_previous.empty() || m_hysteresis <= 0.0) return best;
    // Last step's points within the slack: one of the same role first, then any.
    const double threshold = bestValue - m_hysteresis * std::abs(bestValue);
    for (bool sameRole : {true, false}) {
      int kept = -1;
      double keptValue = 0.0;
      for (int local = 0; local < static_cast<int>(m_members.size()); ++local) {
        if (isTaken(local)) continue;
        const int role = previousRole(local);
        if (role < 0 || (sameRole && role != takenCount)) continue;
        const double x = value(local);
        if (x < threshold) continue;
        if (kept < 0 || beats(x, id(local), keptValue, id(kept))) {
          kept = local;
          keptValue = x;
        }
      }
      if (kept >= 0) return kept;
    }
    return best;
  }

  int id(int local) const { return m_candidates[m_members[local]].point; }
  double distance(int local) const { return m_candidates[m_members[local]].distance; }
  const Eigen::Vector2d& inPlane(int local) const { return m_inPlane[local]; }

 private:
  // The role the member held last step, or -1.
  int previousRole(int local) const {
    const SelectedContactPoint key{id(local), 0};
    const auto it = std::lower_bound(m_previous.begin(), m_previous.end(), key);
    return (it != m_previous.end() && it->point == key.point) ? it->role : -1;
  }

  const std::vector<ContactCandidate>& m_candidates;
  const std::vector<int>& m_members;
  const std::vector<SelectedContactPoint>& m_previous;
  double m_hysteresis;
  std::vector<Eigen::Vector2d> m_inPlane;
};

void selectPoints(const std::vector<ContactCandidate>& candidates, const std::vector<int>& members,
                  const std::vector<SelectedContactPoint>& previous, double hysteresis, ContactCluster& cluster) {
  cluster.memberCount = static_cast<int>(members.size());
  if (members.size() <= static_cast<std::size_t>(kMaxPointsPerCluster)) {
    cluster.selectedCount = cluster.memberCount;
    std::copy(members.begin(), members.end(), cluster.selected.begin());
    return;
  }
  const ClusterSelector s(candidates, members, cluster.normal, previous, hysteresis);
  std::array<int, kMaxPointsPerCluster> local{};
  local[0] = s.pick(local, 0, [&](int k) { return -s.distance(k); });  // (a) the deepest
  const Eigen::Vector2d a = s.inPlane(local[0]);
  local[1] = s.pick(local, 1, [&](int k) { return (s.inPlane(k) - a).norm(); });  // (b) farthest from (a)
  const Eigen::Vector2d b = s.inPlane(local[1]);
  local[2] = s.pick(local, 2, [&](int k) { return triangleArea(a, b, s.inPlane(k)); });  // (c) largest triangle
  const Eigen::Vector2d c = s.inPlane(local[2]);
  local[3] = s.pick(local, 3, [&](int k) { return hullArea(a, b, c, s.inPlane(k)); });  // (d) largest quad
  cluster.selectedCount = kMaxPointsPerCluster;
  for (int i = 0; i < kMaxPointsPerCluster; ++i) cluster.selected[i] = members[local[i]];
}

Vec3 meanNormal(const std::vector<ContactCandidate>& candidates, const std::vector<int>& members,
                const Vec3& fallback) {
  Vec3 sum = Vec3::Zero();
  for (int m : members) sum += candidates[m].normal;
  const double length = sum.norm();
  return length > tolerance::kMinDirectionLength ? Vec3(sum / length)
                                                 : fallback;  // opposed normals cancel: keep the seed's
}

/// The members' centroid and their mean distance from it in the cluster's plane (ContactCluster::spread).
void setSpread(const std::vector<ContactCandidate>& candidates, const std::vector<int>& members,
               ContactCluster& cluster) {
  if (members.empty()) return;
  Vec3 centroid = Vec3::Zero();
  for (int m : members) centroid += candidates[m].position;
  centroid /= double(members.size());
  double sum = 0.0;
  for (int m : members) {
    const Vec3 offset = candidates[m].position - centroid;
    sum += (offset - offset.dot(cluster.normal) * cluster.normal).norm();
  }
  cluster.centroid = centroid;
  cluster.spread = sum / double(members.size());
}

}  // namespace

void ContactReductionSettings::validate() const {
  if (!(clusterCosine >= -1.0 && clusterCosine <= 1.0)) {
    throw Error("contact reduction: clusterCosine must be in [-1, 1]");
  }
  if (maxClusters < 1 || maxClusters > kMaxContactClusters) {
    throw Error("contact reduction: maxClusters must be in 1.." + std::to_string(kMaxContactClusters));
  }
  if (!(hysteresis >= 0.0 && hysteresis < 1.0)) throw Error("contact reduction: hysteresis must be in [0, 1)");
}

std::vector<SelectedContactPoint> ReducedContacts::selectedPoints(
    const std::vector<ContactCandidate>& candidates) const {
  std::vector<SelectedContactPoint> points;
  for (int k = 0; k < clusterCount; ++k) {
    for (int i = 0; i < clusters[k].selectedCount; ++i) {
      points.push_back({candidates[clusters[k].selected[i]].point, i});
    }
  }
  std::sort(points.begin(), points.end());
  return points;
}

ReducedContacts reduceContacts(const std::vector<ContactCandidate>& candidates,
                               const ContactReductionSettings& settings,
                               const std::vector<SelectedContactPoint>& previous) {
  settings.validate();
  if (!std::is_sorted(previous.begin(), previous.end())) {
    throw Error("contact reduction: previous must be sorted by point id");
  }
  for (const ContactCandidate& c : candidates) {
    if (!c.position.allFinite() || !c.normal.allFinite() || !std::isfinite(c.distance)) {
      throw Error("contact reduction: candidate of point " + std::to_string(c.point) + " is not finite");
    }
  }
  ReducedContacts out;
  const int count = static_cast<int>(candidates.size());
  // Shallowest-first order, ties by point id: seeds and leftovers are visited in it, so the input order is moot.
  std::vector<int> order(count);
  for (int i = 0; i < count; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int x, int y) {
    const ContactCandidate& a = candidates[x];
    const ContactCandidate& b = candidates[y];
    return a.distance != b.distance ? a.distance < b.distance : a.point < b.point;
  });

  std::vector<int> clusterOf(count, -1);
  std::array<std::vector<int>, kMaxContactClusters> members;
  std::array<Vec3, kMaxContactClusters> seedNormal;
  std::size_t next = 0;  // first position in `order` that may be unassigned
  while (out.clusterCount < settings.maxClusters) {
    while (next < order.size() && clusterOf[order[next]] >= 0) ++next;
    if (next == order.size()) break;
    const int k = out.clusterCount++;
    const int seed = order[next];
    seedNormal[k] = candidates[seed].normal;
    for (std::size_t i = next; i < order.size(); ++i) {
      const int j = order[i];
      if (clusterOf[j] >= 0) continue;
      if (j == seed || candidates[j].normal.dot(seedNormal[k]) >= settings.clusterCosine) {
        clusterOf[j] = k;
        members[k].push_back(j);
      }
    }
  }
  // Leftovers join the cluster of the nearest mean normal (the means before any leftover joins: order-free).
  std::array<Vec3, kMaxContactClusters> means;
  for (int k = 0; k < out.clusterCount; ++k) means[k] = meanNormal(candidates, members[k], seedNormal[k]);
  for (int j : order) {
    if (clusterOf[j] >= 0) continue;
    int nearest = 0;
    for (int k = 1; k < out.clusterCount; ++k) {
      if (candidates[j].normal.dot(means[k]) > candidates[j].normal.dot(means[nearest])) nearest = k;
    }
    clusterOf[j] = nearest;
    members[nearest].push_back(j);
  }
  for (int k = 0; k < out.clusterCount; ++k) {
    std::sort(members[k].begin(), members[k].end(), [&](int x, int y) {
      const ContactCandidate& a = candidates[x];
      const ContactCandidate& b = candidates[y];
      return a.distance != b.distance ? a.distance < b.distance : a.point < b.point;
    });
    out.clusters[k].normal = meanNormal(candidates, members[k], seedNormal[k]);
    setSpread(candidates, members[k], out.clusters[k]);
    selectPoints(candidates, members[k], previous, settings.hysteresis, out.clusters[k]);
  }
  return out;
}

}  // namespace sdfccd
