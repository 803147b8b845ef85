/// @file
/// @brief detail::AxisCertificates: the coherent query's second certificate test, which charges a front node's
/// motion per axis of the field instead of by its length (axis_lipschitz_bounds.h). Private to the core: used by
/// CoherentQuery (rigid_ccd_coherent.h) when RigidCcdCoherence::axisCertificates is on.
///
/// @details A Phi certificate of node e (centre c_k at pose P_k, clearance phi(c_k), radius rho) records the block
/// of c_k. A point q below the node is within rho of c_k at P_k and moves by dq = (R - R_k) q + (t - t_k) at a pose
/// (R, t) of the step, so per axis |dq_a| <= D_a = |row_a(R - R_k)| reach(e) + |t_a - t_k,a| (reach: the node's
/// largest distance from the shell origin; each end pose of the step bounds the segment between them, as
/// |dq_a| is convex along it). The straight path from c_k to q's position has per-axis extents at most
/// |(q_k - c_k)_a| + D_a, so with the block's bounds (G, |G| <= norm)
///   phi(q) >= phi(c_k) - norm rho - (G_x D_x + G_y D_y + G_z D_z),
/// provided that path stays within the block's reach (rho + D_x + D_y + D_z <= reach) and in the box (q's
/// position outside the box cannot touch: the segment query sees nothing there; inside, the box is convex).
/// The node cannot touch when that lower bound exceeds sigma, with the same relative slack against rounding as
/// the isotropic room (roomOf in rigid_ccd_coherent.h). Deep in a hole with an axis-aligned wall, G along the
/// wall is ~0, so sliding along it does not use up the clearance: only the motion across the wall does.
/// Only GridFields carry the bounds; other fields never get an axis certificate (block -1).
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <type_traits>
#include <vector>

#include "sdfccd/ccd/axis_lipschitz_bounds.h"
#include "sdfccd/ccd/rigid_ccd_coherence.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/tolerances.h"

namespace sdfccd {
namespace detail {

template <class Field>
class AxisCertificates {
 public:
  AxisCertificates() = default;
  /// Takes the shared bounds of the field when the history asks for axis certificates (GridField only) and the
  /// per-pose motion of this step.
  /// `rootReach`: the tree root's largest distance from the shell origin (every point's bound).
  /// `startsAtLastEnd`: the start pose is the last query's end (RigidCcdCoherence::lastAxisToEnd holds the kept
  /// poses' distances to it, all but the newest).
  AxisCertificates(RigidCcdCoherence& cache, const Field& field, const Rigid& start, const Rigid& end, double rootReach,
                   bool startsAtLastEnd) {
    if constexpr (std::is_same_v<Field, GridField>) {
      if (!cache.axisCertificates) return;
      if (!cache.axisBounds) cache.axisBounds = sharedAxisLipschitzBounds(field);
      m_bounds = cache.axisBounds.get();
      // The rounding slack on the coordinates that the isotropic room keeps (roomOf: eps (|c| + root reach)), with
      // |c| bounded by the box's farthest corner (a centre with a block lies in the box).
      const Box3& box = m_bounds->box();
      const Vec3 farthest = box.min().cwiseAbs().cwiseMax(box.max().cwiseAbs());
      m_coordinates = tolerance::kRelativeSlack * (farthest.norm() + rootReach);
      // Per kept pose, the largest per-axis motion over the step's two poses: |row_a(R - R_k)| at 2k, |t_a - t_k,a|
      // at 2k + 1.
      // Per kept pose, the per-axis distance to the end pose (kept for the next query: RigidCcdCoherence::lastEnd),
      // and to the start pose (from the last query when it ended there).
      const std::size_t n = cache.poses.size();
      const std::size_t known = startsAtLastEnd && cache.lastAxisToEnd.size() + 2 == 2 * n ? n - 1 : 0;
      std::vector<Vec3>& toEnd = cache.scratchAxisToEnd;
      std::vector<Vec3>& motion = cache.scratchAxisMotion;
      toEnd.resize(2 * n);
      motion.resize(2 * n);
      for (std::size_t k = 0; k < n; ++k) {
        axisDistance(cache.poses[k], end, toEnd[2 * k], toEnd[2 * k + 1]);
        Vec3 rows, translation;
        if (k < known) {
          rows = cache.lastAxisToEnd[2 * k];
          translation = cache.lastAxisToEnd[2 * k + 1];
        } else {
          axisDistance(cache.poses[k], start, rows, translation);
        }
        for (int a = 0; a < 3; ++a) {
          motion[2 * k][a] = std::max(rows[a], toEnd[2 * k][a]);
          motion[2 * k + 1][a] = std::max(translation[a], toEnd[2 * k + 1][a]);
        }
      }
      m_motion = motion.data();
      m_toEnd = &toEnd;
    } else {
      (void)cache, (void)field, (void)start, (void)end, (void)rootReach, (void)startsAtLastEnd;
    }
  }

  bool enabled() const { return m_bounds != nullptr; }
  /// Per kept pose, the per-axis distance to this step's end pose (2 per pose, as the motion); null when off.
  const std::vector<Vec3>* toEnd() const { return m_toEnd; }

  /// The block of a certificate's centre (field frame), -1 when off or outside the box.
  int blockOf(const Vec3& centreInSdf) const { return m_bounds ? m_bounds->blockOf(centreInSdf) : -1; }

  /// Can no point below the node of `e` (radius `radius`, largest distance from the shell origin `reach`) reach
  /// sigma during the step? `headroom` > 1 asks for room to spare (the motion counted that many times).
  bool holds(const RigidCcdCoherence::Entry& e, double radius, double reach, double sigma, double headroom) const {
    if (m_bounds == nullptr || e.block < 0 || e.kind != RigidCcdCoherence::Kind::Phi) return false;
    const Vec3* m = m_motion + 2 * e.pose;
    const Vec3 d = headroom * (m[0] * reach + m[1]);
    const AxisLipschitzBounds::Block& g = m_bounds->block(e.block);
    if (!((radius + d.sum()) * tolerance::kBoundGrowth < m_bounds->reach())) return false;
    constexpr double eps = tolerance::kRelativeSlack;
    const double margin = e.clearance - sigma - eps * (std::abs(e.clearance) + std::abs(sigma)) - m_coordinates;
    const double drop = static_cast<double>(g.norm) * radius + static_cast<double>(g.x) * d.x() +
                        static_cast<double>(g.y) * d.y() + static_cast<double>(g.z) * d.z();
    return drop * tolerance::kBoundGrowth < margin * (1.0 - eps);
  }

 private:
  /// |row_a(R_q - R_p)| and |t_q,a - t_p,a| per axis.
  static void axisDistance(const Rigid& p, const Rigid& q, Vec3& outRotationRows, Vec3& outTranslation) {
    for (int a = 0; a < 3; ++a) {
      outRotationRows[a] = (q.linear().row(a) - p.linear().row(a)).norm();
      outTranslation[a] = std::abs(q.translation()[a] - p.translation()[a]);
    }
  }

  const AxisLipschitzBounds* m_bounds = nullptr;
  const Vec3* m_motion = nullptr;              // the history's scratchAxisMotion
  const std::vector<Vec3>* m_toEnd = nullptr;  // the history's scratchAxisToEnd
  double m_coordinates = 0.0;                  // rounding slack on the coordinates (the constructor)
};

}  // namespace detail
}  // namespace sdfccd
