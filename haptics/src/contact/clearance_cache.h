/// @file
/// @brief ClearanceCache: the constraint method's test of which shell points provably cannot reach the contact level
/// set during a move against the fixed field (god_object.h, "Clearance cache"; internal to the haptics library).
///
/// @details Per point it keeps a travel budget: (phi - sigma) / L plus the body's travel sums at the point's last
/// evaluation, where the travel of a point is bounded by the sum over moves of |translation of the centre| +
/// |rotation angle| * |point - centre|. Grid fields use the bound of the point's neighbourhood
/// (local_lipschitz_bounds.h) within its reach, and with axis certificates the per-axis bounds of the point's block
/// (axis_lipschitz_bounds.h) against the per-axis travel sums.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <type_traits>
#include <vector>

#include "sdfccd/ccd/axis_lipschitz_bounds.h"
#include "sdfccd/field/field_culling_bounds.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/haptics/local_lipschitz_bounds.h"
#include "sdfccd/math_types.h"
#include "sdfccd/shell/point_tree.h"
#include "sdfccd/tolerances.h"

namespace sdfccd::haptics {

/// `v` rounded down to a float.
inline float roundedDown(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

template <class Field>
class ClearanceCache {
 public:
  /// The cache of `tree`'s points against `field`; `axisCertificates`: grid fields also keep per-axis records.
  ClearanceCache(const PointTree& tree, const Field& field, bool axisCertificates) : m_tree(tree), m_field(field) {
    m_bounds = fieldCullingBounds(field);
    const std::size_t n = static_cast<std::size_t>(tree.pointCount());
    m_skip.assign(n, 0);
    m_clearanceBudget.assign(n, -std::numeric_limits<float>::infinity());  // unknown: evaluate first
    m_pointRadius.resize(n);
    for (std::size_t p = 0; p < n; ++p) {
      // Rounded up to float: a bound of |point - centre| (the shell frame's origin is the centre).
      const double r = tree.shell().positions[p].norm();
      float f = static_cast<float>(r);
      if (static_cast<double>(f) < r) f = std::nextafter(f, std::numeric_limits<float>::infinity());
      m_pointRadius[p] = f;
    }
    if constexpr (std::is_same_v<Field, GridField>) {
      m_local = LocalLipschitzBounds(field.grid());
      if (axisCertificates) {
        m_axisBounds = sharedAxisLipschitzBounds(field);
        m_axisReach = m_axisBounds->reach();
        m_axisRecords.assign(n, AxisRecord{});
      }
    }
  }

  /// Per point, 1 for the points in `contactPoints` when `ignoreContacts` and for those that cannot reach `sigma` on
  /// the move start -> end (poses of the shell in the field's frame); the CCD's ignore list.
  const std::vector<std::uint8_t>& markUnreachablePoints(const Rigid& start, const Rigid& end, double sigma,
                                                         bool ignoreContacts, const std::vector<int>& contactPoints);

 private:
  // Per point whose last evaluation was in the field's box (grid fields, axis certificates): its clearance, block
  // and the travel sums then.
  struct AxisRecord {
    // The evaluation point's block bounds (axis_lipschitz_bounds.h), copied so that the check reads one record.
    float gx = 0.0f, gy = 0.0f, gz = 0.0f, gNorm = 0.0f;
    // m_travelAxis and m_travelRotation at the evaluation, rounded down (the travel since is overestimated).
    float travelX = 0.0f, travelY = 0.0f, travelZ = 0.0f, travelRotation = 0.0f;
    float clearance = -1.0f;  // phi - sigma less the rounding slack, rounded down (model units); <= 0: no record
  };
  /// Does a point's axis record rule out reaching sigma after the travel so far (radius: |point - centre|)?
  bool axisRecordHolds(const AxisRecord& record, double radius) const {
    if (!(record.clearance > 0.0f)) return false;
    const double dx = m_travelAxis.x() - static_cast<double>(record.travelX);
    const double dy = m_travelAxis.y() - static_cast<double>(record.travelY);
    const double dz = m_travelAxis.z() - static_cast<double>(record.travelZ);
    const double dR = (m_travelRotation - static_cast<double>(record.travelRotation)) * radius;
    if (!((dx + dy + dz + dR) * tolerance::kBoundGrowth < m_axisReach)) return false;
    const double drop = static_cast<double>(record.gx) * dx + static_cast<double>(record.gy) * dy +
                        static_cast<double>(record.gz) * dz + static_cast<double>(record.gNorm) * dR;
    return drop * tolerance::kBoundGrowth < static_cast<double>(record.clearance);
  }
  /// Evaluates phi where point p starts the move (`pointInSdf`) and renews its budget and axis record.
  void evaluate(std::size_t p, const Vec3& pointInSdf, double sigma, double radius, double translationBefore,
                double rotationBefore, const Vec3& axisBefore);

  const PointTree& m_tree;
  const Field& m_field;
  FieldCullingBounds m_bounds;
  LocalLipschitzBounds m_local;  // grid fields only
  std::vector<std::uint8_t> m_skip;
  std::vector<float> m_clearanceBudget;                     // model units (see markUnreachablePoints)
  std::vector<float> m_pointRadius;                         // |point - centre|, rounded up
  double m_travelTranslation = 0.0;                         // sum of |centre translation| over the moves (model units)
  double m_travelRotation = 0.0;                            // sum of rotation angles over the moves (rad)
  double m_axisReach = 0.0;                                 // model units: m_axisBounds->reach()
  std::shared_ptr<const AxisLipschitzBounds> m_axisBounds;  // grid fields with axis certificates
  std::vector<AxisRecord> m_axisRecords;
  Vec3 m_travelAxis = Vec3::Zero();  // per field axis, sum of |centre translation along it| over the moves
};

// Per point, m_clearanceBudget holds (phi - sigma) / L + travelTranslation + travelRotation * radius at its last
// evaluation (rounded down to float), so the point is safe while budget > travelTranslation + travelRotation * radius
// now, travel included.
template <class Field>
const std::vector<std::uint8_t>& ClearanceCache<Field>::markUnreachablePoints(const Rigid& start, const Rigid& end,
                                                                              double sigma, bool ignoreContacts,
                                                                              const std::vector<int>& contactPoints) {
  const double stepTranslation = (end.translation() - start.translation()).norm();
  const double stepRotation = Eigen::AngleAxisd(end.linear() * start.linear().transpose()).angle();
  const double translationBefore = m_travelTranslation;
  const double rotationBefore = m_travelRotation;
  const Vec3 axisBefore = m_travelAxis;
  // Slack against rounding in the accumulated sums.
  m_travelTranslation += stepTranslation * tolerance::kBoundGrowth;
  m_travelRotation += stepRotation * tolerance::kBoundGrowth;
  // Rounded up: the axis certificates compare differences of these sums (whose own rounding kBoundGrowth covers).
  constexpr double up = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
    m_travelAxis[a] = std::nextafter(
        m_travelAxis[a] + std::abs(end.translation()[a] - start.translation()[a]) * tolerance::kBoundGrowth, up);
  m_travelRotation = std::nextafter(m_travelRotation, up);
  const double travelT = m_travelTranslation;
  const double travelR = m_travelRotation;
  const std::size_t n = m_skip.size();
  const std::vector<Vec3>& positions = m_tree.shell().positions;
  for (std::size_t p = 0; p < n; ++p) {
    const double radius = static_cast<double>(m_pointRadius[p]);
    if (static_cast<double>(m_clearanceBudget[p]) > travelT + travelR * radius) {
      m_skip[p] = 1;
      continue;
    }
    if (m_axisBounds && axisRecordHolds(m_axisRecords[p], radius)) {
      m_skip[p] = 1;
      continue;
    }
    m_skip[p] = 0;
    // Out of budget: evaluate phi where the point starts this move.
    evaluate(p, start * positions[p], sigma, radius, translationBefore, rotationBefore, axisBefore);
  }
  if (ignoreContacts)
    for (const int p : contactPoints) m_skip[static_cast<std::size_t>(p)] = 1;
  return m_skip;
}

template <class Field>
void ClearanceCache<Field>::evaluate(std::size_t p, const Vec3& pointInSdf, double sigma, double radius,
                                     double translationBefore, double rotationBefore, const Vec3& axisBefore) {
  const double lipschitz = m_bounds.lipschitz * tolerance::kBoundGrowth;
  const double travelT = m_travelTranslation;
  const double travelR = m_travelRotation;
  // Inside the box: phi there. Outside (the segment query sees no contact there): a path into the box crosses a face
  // (phi >= boundaryMin) after at least the distance to the box, so L * that distance + boundaryMin plays the part
  // of phi.
  const double phi = m_bounds.bounded && !m_bounds.box.contains(pointInSdf)
                         ? m_bounds.lipschitz * m_bounds.box.exteriorDistance(pointInSdf) + m_bounds.boundaryMin
                         : m_field.distance(pointInSdf);
  // A relative margin against the different rounding of the segment query's own evaluation of phi, on the
  // magnitudes involved: phi and sigma, and the point's coordinates (its position and phi round relative to them;
  // far from the field's origin phi can be small beside them).
  const double clearance =
      phi - sigma - tolerance::kRelativeSlack * (std::abs(phi) + std::abs(sigma) + pointInSdf.norm());
  double allowedTravel = clearance / lipschitz;
  if (!m_local.empty() && m_bounds.box.contains(pointInSdf))
    allowedTravel =
        std::min(clearance / (m_local.lipschitzNear(pointInSdf) * tolerance::kBoundGrowth), m_local.reach());
  const double budget = allowedTravel + translationBefore + rotationBefore * radius;
  float f = static_cast<float>(budget);
  if (static_cast<double>(f) > budget) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  m_clearanceBudget[p] = f;
  m_skip[p] = static_cast<double>(f) > travelT + travelR * radius;
  if (m_axisBounds) {
    AxisRecord& record = m_axisRecords[p];
    const int block = m_axisBounds->blockOf(pointInSdf);  // -1 outside the box: no axis certificate
    record.clearance = block < 0 ? -1.0f : roundedDown(clearance);
    if (block >= 0) {
      const AxisLipschitzBounds::Block& g = m_axisBounds->block(block);
      record.gx = g.x, record.gy = g.y, record.gz = g.z, record.gNorm = g.norm;
      record.travelX = roundedDown(axisBefore.x());
      record.travelY = roundedDown(axisBefore.y());
      record.travelZ = roundedDown(axisBefore.z());
      record.travelRotation = roundedDown(rotationBefore);
    }
    if (!m_skip[p]) m_skip[p] = axisRecordHolds(record, radius);
  }
}

}  // namespace sdfccd::haptics
