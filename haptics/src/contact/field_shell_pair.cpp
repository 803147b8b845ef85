/// @file
/// @brief The field-shell pair: an obstacle of a scene's "obstacles" list, static or moving, against the tool, for both
/// haptic methods (see haptic_obstacles.h and obstacle_pair.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "contact/obstacle_pair.h"
#include "contact/pair_contacts.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/haptics/rigid_body_state.h"
#include "sdfccd/tolerances.h"

namespace sdfccd::haptics {

namespace {

/// A (shell, field) pair: the tool's shell against an obstacle's field (toolIsShell), or an obstacle's shell
/// against the tool's field.
template <class Field>
class FieldShellPair final : public ObstaclePair {
 public:
  FieldShellPair(int index, const ObstaclePath& path, double toolRadius, const PointTree& tree, const Field& field,
                 bool toolIsShell)
      : ObstaclePair(index, path, toolRadius),
        m_tree(tree),
        m_field(field),
        m_toolIsShell(toolIsShell),
        m_contacts(static_cast<std::size_t>(tree.pointCount())) {}

  void nearRows(const Rigid& worldFromTool, const GodObjectSettings& s, double level,
                std::vector<GodObjectContact>& rows) override {
    discreteQuery(worldFromTool, s.sigma + level);
    for (const PointContact& c : m_contacts.ccd().contacts) {
      GodObjectContact contact;
      if (makeContact(worldFromTool, c.point, contact)) rows.push_back(contact);
    }
    m_contacts.addCandidates();
  }

  double continuousFraction(const Rigid& start, const Rigid& end, const GodObjectSettings& s,
                            GodObjectStepResult& out) override {
    RigidCcdSettings ccd = constraintCcdSettings(s, s.sigma);
    ccd.ignoredPoints = s.ignoreContactPoints ? &m_contacts.inContact() : nullptr;
    return m_contacts.continuousFraction(m_tree, m_field, sdfFromShell(start), sdfFromShell(end), s, ccd, out);
  }

  void discreteCandidates(const Rigid& worldFromTool, const GodObjectSettings& s, GodObjectStepResult& out) override {
    discreteQuery(worldFromTool, s.sigma + s.contactThreshold);
    out.segmentQueries += m_contacts.ccd().stats.segmentQueries;
    m_contacts.addCandidates();
  }

  void appendContacts(const Rigid& worldFromTool, const GodObjectSettings& s, std::vector<GodObjectContact>& next,
                      GodObjectStepResult& out) override {
    m_contacts.update(
        [&](int p, GodObjectContact& c) {
          return makeContact(worldFromTool, p, c) && c.distance - s.sigma <= s.contactThreshold;
        },
        next, out);
  }

  void penalty(const ShellMotion& tool, double timestep, const ContactQuerySettings& query, bool consistentGradient,
               ObstaclePenaltySum& sum) override {
    // The obstacle's motion over the tick, with its (constant) velocity.
    const double h = m_timestep > 0.0 ? m_timestep : timestep;
    const Vec6 twist = poseDifference(m_poseStart, m_pose) / h;
    BodyVelocities obstacleVelocity;
    obstacleVelocity.linearStart = obstacleVelocity.linearEnd = twist.head<3>();
    obstacleVelocity.angularStart = obstacleVelocity.angularEnd = twist.tail<3>();
    FieldMotion field;
    ShellMotion shell;
    if (m_toolIsShell) {
      shell = tool;
      field.worldFromSdfStart = m_poseStart;
      field.worldFromSdfEnd = m_pose;
      field.velocity = obstacleVelocity;
    } else {  // the tool's field: its frame is the tool's body frame (origin at the centre of mass)
      field.worldFromSdfStart = tool.worldFromShellStart;
      field.worldFromSdfEnd = tool.worldFromShellEnd;
      field.velocity = tool.velocity;
      shell.worldFromShellStart = m_poseStart;
      shell.worldFromShellEnd = m_pose;
      shell.velocity = obstacleVelocity;
    }
    // The renderer's settings, without its per-pair state: a CCD history or friction anchors kept for one (shell,
    // field) pair must not be handed another pair's query.
    ContactQuerySettings own = query;
    own.coherence = nullptr;
    own.anchors = nullptr;
    queryContacts(m_tree, m_field, shell, field, timestep, own, m_query);
    sum.segmentQueries += m_query.ccd.stats.segmentQueries;
    const PenaltyResult& p = m_query.penalty;
    Vec6 wrench;
    if (m_toolIsShell)
      wrench << p.forceOnShell, p.torqueOnShell;
    else
      wrench << p.forceOnField, p.torqueOnField;  // minus the force on the obstacle's points, about the tool's centre
    sum.wrenchOnTool += wrench;
    sum.contactCount += p.contactCount;
    sum.maxPenetration = std::max(sum.maxPenetration, p.maxPenetration);
    Mat6 k = Mat6::Zero();
    addGradient(tool.worldFromShellEnd, field.worldFromSdfEnd, shell.worldFromShellEnd, query, consistentGradient, k);
    sum.gradient += k;
    // The implicit step (penalty_renderer.h) predicts the next tick's contact force from the tool's own motion,
    // F + h K v; a moving obstacle changes it too, as if the tool moved by minus the obstacle's motion. That motion,
    // as a twist about the tool's centre c (the obstacle's velocity at c, and its spin), is fed forward here:
    // F - h K V_obstacle, so that the step sees F + h K (v - V_obstacle). Without it a pushing wall presses v h
    // deeper than the force balance asks (the contact lags the wall by one tick).
    if (m_timestep > 0.0 && !twist.isZero(0.0)) {
      Vec6 atTool;
      atTool << twist.head<3>() + twist.tail<3>().cross(tool.worldFromShellEnd.translation() - m_pose.translation()),
          twist.tail<3>();
      sum.wrenchOnTool -= timestep * (k * atTool);
    }
  }

  double penetration(const Rigid& worldFromTool) override {
    return deepestPenetration(m_tree, m_field, sdfFromShell(worldFromTool), m_contacts.ccd());
  }

 private:
  Rigid worldFromShell(const Rigid& worldFromTool) const { return m_toolIsShell ? worldFromTool : m_pose; }
  Rigid worldFromField(const Rigid& worldFromTool) const { return m_toolIsShell ? m_pose : worldFromTool; }
  Rigid sdfFromShell(const Rigid& worldFromTool) const {
    return worldFromField(worldFromTool).inverse() * worldFromShell(worldFromTool);
  }

  /// The points with phi < level at the pose (a zero-length CCD).
  void discreteQuery(const Rigid& worldFromTool, double level) {
    const Rigid at = sdfFromShell(worldFromTool);
    RigidCcdSettings ccd;
    ccd.sigma = level;
    ccd.mode = CcdMode::FirstHit;
    ccd.octree = OctreeMode::Leaves;
    rigidCcd(m_tree, m_field, at, at, ccd, m_contacts.ccd());
  }

  /// The constraint row of shell point `p` at the pose (see haptic_obstacles.h for n's sign); false at a point
  /// with no gradient direction.
  bool makeContact(const Rigid& worldFromTool, int p, GodObjectContact& c) const {
    const Vec3& x = m_tree.shell().positions[static_cast<std::size_t>(p)];
    const Vec3 pointInSdf = sdfFromShell(worldFromTool) * x;
    const Vec3 gradient = worldFromField(worldFromTool).linear() * m_field.gradient(pointInSdf);
    const double len = gradient.norm();
    if (!(len > tolerance::kMinDirectionLength) || !std::isfinite(len)) return false;
    c.point = p;
    c.obstacle = m_index;
    c.normalIntoObstacle = (m_toolIsShell ? -1.0 : 1.0) * gradient / len;
    c.handle = worldFromShell(worldFromTool) * x - worldFromTool.translation();
    c.distance = m_field.distance(pointInSdf);
    return true;
  }

  /// d(wrench on the tool)/d(tool pose) of this pair at the end of the tick, added to `k`. Per point of the shell
  /// with depth d = phi - sigma < 0 and force c u on the shell's point (c = -k d): g the world gradient of phi,
  /// r from the tool's centre to the point, B = [I, -[r]x]. A tool move dx changes d by s g^T B dx (s = +1 when the
  /// point is the tool's, -1 when it is the obstacle's and the tool's field moves past it), and the force on the tool
  /// is s c u; both roles give the same first term -k B^T u g^T B. The geometric terms: the tool's own point turns
  /// its lever (and its shell normal) with it; an obstacle's point stays while the tool's centre moves, which turns
  /// the lever by -dx: d tau = [F]x dx (F the force on the tool).
  void addGradient(const Rigid& worldFromTool, const Rigid& worldFromField, const Rigid& worldFromShellAtEnd,
                   const ContactQuerySettings& query, bool consistentGradient, Mat6& k) const {
    const PenaltySettings& pen = query.penalty;
    const Rigid sdfFromEnd = worldFromField.inverse() * worldFromShellAtEnd;
    const bool shellNormal = pen.direction == PenaltyDirection::ShellNormal;
    const bool everyContact = pen.model == PenaltyModel::Continuous && consistentGradient;
    const PointShell& shell = m_tree.shell();
    const double stiffness = pen.stiffness;
    for (const PointContact& c : m_query.ccd.contacts) {
      if (!(c.depthAtEnd < 0.0) && !(everyContact && !c.intervals.empty())) continue;
      const std::size_t i = static_cast<std::size_t>(c.point);
      const Vec3 pointInSdf = sdfFromEnd * shell.positions[i];
      const Vec3 gradient = worldFromField.linear() * m_field.gradient(pointInSdf);
      const double len = gradient.norm();
      if (!(len > tolerance::kMinDirectionLength)) continue;
      const Vec3 r = worldFromShellAtEnd * shell.positions[i] - worldFromTool.translation();
      Eigen::Matrix<double, 1, 6> gRow;
      gRow.head<3>() = gradient.transpose();
      gRow.tail<3>() = r.cross(gradient).transpose();
      if (!consistentGradient) {
        gRow /= len;
        k.noalias() -= stiffness * gRow.transpose() * gRow;
        continue;
      }
      const Vec3 u = shellNormal ? Vec3(-(worldFromShellAtEnd.linear() * shell.normals[i])) : Vec3(gradient / len);
      Eigen::Matrix<double, 6, 1> uColumn;
      uColumn.head<3>() = u;
      uColumn.tail<3>() = r.cross(u);
      k.noalias() -= stiffness * uColumn * gRow;
      const double depth = m_field.distance(pointInSdf) - pen.sigma;
      if (!(depth < 0.0)) continue;
      const Vec3 onShellPoint = (-stiffness * depth) * u;
      if (m_toolIsShell) {
        k.bottomRightCorner<3, 3>() += crossMatrix(onShellPoint) * crossMatrix(r);
        if (shellNormal) {
          k.topRightCorner<3, 3>() -= crossMatrix(onShellPoint);
          k.bottomRightCorner<3, 3>() -= crossMatrix(r) * crossMatrix(onShellPoint);
        }
      } else {
        k.bottomLeftCorner<3, 3>() += crossMatrix(-onShellPoint);
      }
    }
  }

  const PointTree& m_tree;
  const Field& m_field;
  bool m_toolIsShell;
  PairContacts m_contacts;  // constraint method
  ContactQueryResult m_query;
};

}  // namespace

std::unique_ptr<ObstaclePair> makeFieldShellPair(int index, const ObstaclePath& path, double toolRadius,
                                                 const PointTree& tree, const GridField& field, bool toolIsShell) {
  return std::make_unique<FieldShellPair<GridField>>(index, path, toolRadius, tree, field, toolIsShell);
}

std::unique_ptr<ObstaclePair> makeFieldShellPair(int index, const ObstaclePath& path, double toolRadius,
                                                 const PointTree& tree, const PlaneField& field, bool toolIsShell) {
  return std::make_unique<FieldShellPair<PlaneField>>(index, path, toolRadius, tree, field, toolIsShell);
}

}  // namespace sdfccd::haptics
