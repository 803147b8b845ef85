/// @file
/// @brief The fixed field: one static field at a fixed pose against the tool's shell, the scene's single static
/// object as an obstacle (see obstacle_pair.h), instantiated for every field type of field_interface.h.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <type_traits>
#include <vector>

#include "contact/clearance_cache.h"
#include "contact/obstacle_pair.h"
#include "contact/pair_contacts.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/tolerances.h"

namespace sdfccd::haptics {

namespace {

/// The field's gradient at `pointInSdf`, and for a grid field inside its box also phi there (`outDistance`, else
/// NaN) from the same cell lookup: GridField::gradient and ::distance interpolate that cell each, so the values
/// are bit-identical and a contact pays one lookup instead of two.
template <class Field>
Vec3 gradientWithDistance(const Field& field, const Vec3& pointInSdf, double& outDistance) {
  outDistance = std::numeric_limits<double>::quiet_NaN();
  if constexpr (std::is_same_v<Field, GridField>) {
    if (field.grid().contains(pointInSdf)) {
      Vec3 gradient;
      outDistance = field.grid().interpolate(pointInSdf, gradient);
      return gradient;
    }
  }
  return field.gradient(pointInSdf);
}

/// The tool's shell against one field that never moves. The obstacle's pose is the field's frame (worldFromSdf).
template <class Field>
class FixedFieldPair final : public ObstaclePair {
 public:
  FixedFieldPair(const PointTree& tree, const Field& field, const Rigid& worldFromField)
      : ObstaclePair(0, fixedPath(worldFromField), 0.0),
        m_tree(tree),
        m_field(field),
        m_worldFromSdf(worldFromField),
        m_sdfFromWorld(worldFromField.inverse()),
        m_fieldMotion(FieldMotion::fixed(worldFromField)),
        m_contacts(static_cast<std::size_t>(tree.pointCount())) {}

  void prepareConstraint(const GodObjectSettings& settings) override {
    m_cache.reset();
    if (settings.clearanceCache) m_cache.emplace(m_tree, m_field, settings.axisCertificates);
  }

  // The every-contact query starts from the last tick's front (rigid_ccd_coherence.h): the same contacts bit for
  // bit, fewer field lookups where the shell stays clear of the field between ticks.
  void preparePenalty(const ContactQuerySettings& query, const PenaltyRendererSettings& settings,
                      const Rigid& worldFromToolStart) override {
    m_coherent = settings.coherentCcd;
    if (!m_coherent) return;
    m_coherence.axisCertificates = settings.axisCertificates;
    // Builds the history (per-node tables and a first front) with a zero-length query at the start pose, so that the
    // first tick of the loop does not pay for it. Its result is not used.
    ContactQuerySettings warm = query;
    warm.coherence = &m_coherence;
    warm.integratePenalty = false;
    queryContacts(m_tree, m_field, ShellMotion::fixed(worldFromToolStart), m_fieldMotion, settings.timestep, warm,
                  m_query);
  }

  void nearRows(const Rigid& worldFromTool, const GodObjectSettings& s, double level,
                std::vector<GodObjectContact>& rows) override {
    const Rigid at = m_sdfFromWorld * worldFromTool;
    RigidCcdSettings ccd = constraintCcdSettings(s, s.sigma + level);
    rigidCcd(m_tree, m_field, at, at, ccd, m_contacts.ccd());
    for (const PointContact& c : m_contacts.ccd().contacts) {
      GodObjectContact contact;
      if (makeContact(worldFromTool, at, c.point, nullptr, contact)) rows.push_back(contact);
    }
    m_contacts.addCandidates();
  }

  // Step 5 (god_object.h): the earliest contact fraction of the move; collects the reported points as candidates.
  double continuousFraction(const Rigid& worldStart, const Rigid& worldEnd, const GodObjectSettings& s,
                            GodObjectStepResult& out) override {
    const Rigid start = m_sdfFromWorld * worldStart;
    const Rigid end = m_sdfFromWorld * worldEnd;
    RigidCcdSettings ccd = constraintCcdSettings(s, s.sigma);
    ccd.ignoredPoints = s.ignoreContactPoints ? &m_contacts.inContact() : nullptr;
    if (m_cache) {
      ccd.ignoredPoints =
          &m_cache->markUnreachablePoints(start, end, s.sigma, s.ignoreContactPoints, m_contacts.points());
      ccd.useTree = false;  // the few points left are visited one by one (the same leaf query as the tree's)
    }
    return m_contacts.continuousFraction(m_tree, m_field, start, end, s, ccd, out);
  }

  // The discrete variant: every point near the surface at the new pose.
  void discreteCandidates(const Rigid& worldFromTool, const GodObjectSettings& s, GodObjectStepResult& out) override {
    const Rigid at = m_sdfFromWorld * worldFromTool;
    RigidCcdSettings ccd;
    ccd.sigma = s.sigma + s.contactThreshold;
    ccd.mode = CcdMode::FirstHit;
    ccd.octree = s.octree;
    ccd.threads = s.threads;
    rigidCcd(m_tree, m_field, at, at, ccd, m_contacts.ccd());
    out.segmentQueries += m_contacts.ccd().stats.segmentQueries;
    m_contacts.addCandidates();
  }

  // Step 6: the contact set at the new pose, from the candidates and the last contacts.
  void appendContacts(const Rigid& worldFromTool, const GodObjectSettings& s, std::vector<GodObjectContact>& next,
                      GodObjectStepResult& out) override {
    const Rigid sdfFromTool = m_sdfFromWorld * worldFromTool;
    m_contacts.update([&](int p, GodObjectContact& c) { return makeContact(worldFromTool, sdfFromTool, p, &s, c); },
                      next, out);
  }

  void penalty(const ShellMotion& tool, double timestep, const ContactQuerySettings& query, bool consistentGradient,
               ObstaclePenaltySum& sum) override {
    ContactQuerySettings own = query;
    own.coherence = m_coherent ? &m_coherence : nullptr;
    queryContacts(m_tree, m_field, tool, m_fieldMotion, timestep, own, m_query);
    sum.segmentQueries = m_query.ccd.stats.segmentQueries;
    sum.certifiedNodes = m_query.ccd.stats.certified;
    const PenaltyResult& p = m_query.penalty;
    sum.wrenchOnTool << p.forceOnShell, p.torqueOnShell;  // the only pair of its source
    sum.contactCount = p.contactCount;
    sum.maxPenetration = p.maxPenetration;
    addGradient(tool.worldFromShellEnd, query.penalty, consistentGradient, sum.gradient);
  }

  double penetration(const Rigid& worldFromTool) override {
    return deepestPenetration(m_tree, m_field, m_sdfFromWorld * worldFromTool, m_contacts.ccd());
  }

 private:
  static ObstaclePath fixedPath(const Rigid& worldFromField) {
    ObstaclePath path;
    path.worldFromObstacle = worldFromField;
    return path;
  }

  /// The constraint row of shell point `p` at the tool's pose (`sdfFromTool` in the field's frame): n = -grad(phi)
  /// (into the field), r from the centre to the point. False at a point with no gradient direction (a medial point)
  /// and, with `within`, at a point farther than its contactThreshold from the contact level set.
  bool makeContact(const Rigid& worldFromTool, const Rigid& sdfFromTool, int p, const GodObjectSettings* within,
                   GodObjectContact& c) const {
    const Vec3& pointInShell = m_tree.shell().positions[static_cast<std::size_t>(p)];
    const Vec3 pointInSdf = sdfFromTool * pointInShell;
    const double phi = m_field.distance(pointInSdf);
    if (within && !(phi - within->sigma <= within->contactThreshold)) return false;
    const Vec3 gradient = m_field.gradient(pointInSdf);
    const double len = gradient.norm();
    if (!(len > tolerance::kMinDirectionLength) || !std::isfinite(len)) return false;
    const Mat3 worldFromSdfRotation = m_worldFromSdf.linear();
    c.point = p;
    c.obstacle = m_index;
    c.normalIntoObstacle = -(worldFromSdfRotation * gradient) / len;
    c.handle = worldFromTool.linear() * pointInShell;
    c.distance = phi;
    return true;
  }

  /// d(contact wrench on the tool) / d(tool pose) at the end of the tick, added to `k` (zero on entry), summed over
  /// the points in contact. Per point: force f = c u with c = -k d >= 0 (d = phi - sigma < 0) and u the force's
  /// direction, handle r (centre of mass to the point), B = [I, -[r]x] (a pose change dx moves the point by B dx), g
  /// the world gradient of phi (dd/dp = g). Then
  ///   d f   = -k u g^T B dx + c du,      du = dtheta x u  (the shell normal turns with the object; the field's
  ///                                                        gradient direction does not, its curvature is dropped)
  ///   d tau = [r]x d f + dr x f,          dr x f = (dtheta x r) x f = [f]x [r]x dtheta   (the geometric term)
  /// so K = -k B^T u g^T B + [[0, -[f]x], [0, -[r]x [f]x + [f]x [r]x]] (shell normal; without the c du terms for the
  /// gradient direction). Not symmetric; the step solves it with LU. consistentGradient = false: the symmetric
  /// -k B^T n n^T B with n the unit gradient (the force's direction and the torque's lever dropped).
  ///
  /// Continuous model: every point the CCD found in contact during the step, not only those inside at its end. A
  /// point that left contact during the step still pushes during the next one (its force is the step's average,
  /// eq. 5); without its stiffness in the implicit solve that push is explicit, and once k h^2 / m exceeds ~1 it
  /// throws the object out of the contact. Its depth gradient is taken at the end pose (phi is defined everywhere);
  /// its force-order terms only when it is still inside.
  void addGradient(const Rigid& worldFromToolEnd, const PenaltySettings& contact, bool consistentGradient,
                   Mat6& gradientSum) const {
    const Rigid& sdfFromEnd = m_query.sdfFromShellEnd;
    const Mat3 worldFromSdfRotation = m_worldFromSdf.linear();
    const Mat3 worldFromBody = worldFromToolEnd.linear();
    const double k = contact.stiffness;
    const double sigma = contact.sigma;
    const bool shellNormal = contact.direction == PenaltyDirection::ShellNormal;
    const PointShell& shell = m_tree.shell();
    const bool everyContact = contact.model == PenaltyModel::Continuous && consistentGradient;
    for (const PointContact& c : m_query.ccd.contacts) {
      if (!(c.depthAtEnd < 0.0) && !(everyContact && !c.intervals.empty())) continue;
      const std::size_t i = static_cast<std::size_t>(c.point);
      const Vec3 pointInSdf = sdfFromEnd * shell.positions[i];
      double distance;  // phi at the point when the gradient's lookup gave it (NaN: not yet)
      const Vec3 gradient = worldFromSdfRotation * gradientWithDistance(m_field, pointInSdf, distance);
      const double len = gradient.norm();
      if (!(len > tolerance::kMinDirectionLength)) continue;
      const Vec3 r = worldFromBody * shell.positions[i];
      Eigen::Matrix<double, 1, 6> gRow;  // g^T B
      gRow.head<3>() = gradient.transpose();
      gRow.tail<3>() = r.cross(gradient).transpose();
      if (!consistentGradient) {
        gRow /= len;
        gradientSum.noalias() -= k * gRow.transpose() * gRow;
        continue;
      }
      const Vec3 u = shellNormal ? Vec3(-(worldFromBody * shell.normals[i])) : Vec3(gradient / len);
      Eigen::Matrix<double, 6, 1> uColumn;  // B^T u
      uColumn.head<3>() = u;
      uColumn.tail<3>() = r.cross(u);
      gradientSum.noalias() -= k * uColumn * gRow;
      const double depth = (std::isnan(distance) ? m_field.distance(pointInSdf) : distance) - sigma;
      if (!(depth < 0.0)) continue;
      const Vec3 f = (-k * depth) * u;
      gradientSum.bottomRightCorner<3, 3>() += crossMatrix(f) * crossMatrix(r);  // the geometric term of the torque
      if (shellNormal) {
        gradientSum.topRightCorner<3, 3>() -= crossMatrix(f);
        gradientSum.bottomRightCorner<3, 3>() -= crossMatrix(r) * crossMatrix(f);
      }
    }
  }

  const PointTree& m_tree;
  const Field& m_field;
  Rigid m_worldFromSdf;
  Rigid m_sdfFromWorld;
  FieldMotion m_fieldMotion;
  // Constraint method.
  PairContacts m_contacts;
  std::optional<ClearanceCache<Field>> m_cache;  // settings.clearanceCache
  // Penalty method.
  bool m_coherent = false;
  RigidCcdCoherence m_coherence;  // the CCD's history across ticks (settings.coherentCcd)
  ContactQueryResult m_query;
};

}  // namespace

template <class Field>
std::unique_ptr<ObstaclePair> makeFixedFieldPair(const PointTree& tree, const Field& field,
                                                 const Rigid& worldFromField) {
  return std::make_unique<FixedFieldPair<Field>>(tree, field, worldFromField);
}

#define SDFCCD_INSTANTIATE_FIXED_FIELD_PAIR(Field) \
  template std::unique_ptr<ObstaclePair> makeFixedFieldPair(const PointTree&, const Field&, const Rigid&);
SDFCCD_FOR_EACH_FIELD(SDFCCD_INSTANTIATE_FIXED_FIELD_PAIR)
#undef SDFCCD_INSTANTIATE_FIXED_FIELD_PAIR

}  // namespace sdfccd::haptics
