/// @file
/// @brief ObstacleContacts: every obstacle's (shell, field) pair with the tool, for both haptic methods (see
/// haptic_obstacles.h).
#include "sdfccd/haptics/haptic_obstacles.h"

#include <algorithm>
#include <cmath>

#include "sdfccd/error.h"
#include "sdfccd/haptics/god_object.h"
#include "sdfccd/haptics/least_distance.h"
#include "sdfccd/haptics/rigid_body_state.h"
#include "sdfccd/tolerances.h"

namespace sdfccd::haptics {

namespace {

/// The cross-product matrix [v]x.
Mat3 crossMatrix(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// The largest |x| over a shell's points (its radius about its frame's origin).
double shellRadius(const PointTree& tree) {
  double r = 0.0;
  for (const Vec3& p : tree.shell().positions) r = std::max(r, p.norm());
  return r;
}

}  // namespace

/// One obstacle against the tool (see haptic_obstacles.h): the role-free part.
class ObstaclePair {
 public:
  ObstaclePair(int index, const ObstaclePath& path, double toolRadius)
      : m_index(index), m_path(path), m_toolRadius(toolRadius) {
    m_pose = m_poseStart = path.poseAt(0.0);
  }
  virtual ~ObstaclePair() = default;

  bool moveTo(double time) {
    m_poseStart = m_pose;
    m_pose = m_path.poseAt(time);
    m_timestep = 0.0;
    return !m_pose.isApprox(m_poseStart, 0.0);
  }
  void moveOver(double time0, double time1) {
    m_poseStart = m_path.poseAt(time0);
    m_pose = m_path.poseAt(time1);
    m_timestep = time1 - time0;
  }
  const Rigid& pose() const { return m_pose; }
  /// How far any point within the tool's reach (plus `margin`) moved with the obstacle since the last move:
  /// |D c - c| + angle(D) (radius + margin), D the obstacle's world displacement, c the tool's centre.
  double moveBound(const Rigid& worldFromTool, double margin) const {
    const Rigid d = m_pose * m_poseStart.inverse();
    const Vec3 c = worldFromTool.translation();
    return (d * c - c).norm() + Eigen::AngleAxisd(d.linear()).angle() * (m_toolRadius + margin);
  }

  /// The push's rows: every point within `level` of the contact level set at the pose (n, r, gap = phi - sigma).
  virtual void nearRows(const Rigid& worldFromTool, const GodObjectSettings& s, double level,
                        std::vector<GodObjectContact>& rows) = 0;
  virtual double continuousFraction(const Rigid& start, const Rigid& end, const GodObjectSettings& s,
                                    GodObjectStepResult& out) = 0;
  virtual void discreteCandidates(const Rigid& worldFromTool, const GodObjectSettings& s, GodObjectStepResult& out) = 0;
  virtual void appendContacts(const Rigid& worldFromTool, const GodObjectSettings& s,
                              std::vector<GodObjectContact>& next, GodObjectStepResult& out) = 0;
  virtual void penalty(const ShellMotion& tool, double timestep, const ContactQuerySettings& query,
                       bool consistentGradient, ObstaclePenaltySum& sum) = 0;
  virtual double penetration(const Rigid& worldFromTool) = 0;

 protected:
  int m_index;
  ObstaclePath m_path;
  double m_toolRadius;
  Rigid m_pose = Rigid::Identity();       // the obstacle now (end of the tick)
  Rigid m_poseStart = Rigid::Identity();  // at the start of the tick (penalty) or the last cycle (constraint)
  double m_timestep = 0.0;                // s, of the motion m_poseStart -> m_pose (penalty)
};

namespace {

/// A (shell, field) pair: the tool's shell against an obstacle's field (toolIsShell), or an obstacle's shell
/// against the tool's field.
template <class Field>
class FieldShellPair final : public ObstaclePair {
 public:
  FieldShellPair(int index, const ObstaclePath& path, double toolRadius, const PointTree& tree, const Field& field,
                 bool toolIsShell)
      : ObstaclePair(index, path, toolRadius), m_tree(tree), m_field(field), m_toolIsShell(toolIsShell) {
    const std::size_t n = static_cast<std::size_t>(tree.pointCount());
    m_inContact.assign(n, 0);
    m_notInContact.assign(n, 1);
  }

  void nearRows(const Rigid& worldFromTool, const GodObjectSettings& s, double level,
                std::vector<GodObjectContact>& rows) override {
    discreteQuery(worldFromTool, s.sigma + level);
    for (const PointContact& c : m_ccd.contacts) {
      GodObjectContact contact;
      if (makeContact(worldFromTool, c.point, contact)) rows.push_back(contact);
      m_candidates.push_back(c.point);
    }
  }

  double continuousFraction(const Rigid& start, const Rigid& end, const GodObjectSettings& s,
                            GodObjectStepResult& out) override {
    const Rigid sdfStart = sdfFromShell(start);
    const Rigid sdfEnd = sdfFromShell(end);
    RigidCcdSettings ccd = querySettings(s, s.sigma);
    ccd.ignoredPoints = s.ignoreContactPoints ? &m_inContact : nullptr;
    rigidCcd(m_tree, m_field, sdfStart, sdfEnd, ccd, m_ccd);
    out.segmentQueries += m_ccd.stats.segmentQueries;
    double fraction = 1.0;
    for (const PointContact& c : m_ccd.contacts) {
      fraction = std::min(fraction, c.fraction);
      m_candidates.push_back(c.point);
    }
    if (s.ignoreContactPoints && s.guardIgnoredPoints && !m_contactPoints.empty())
      fraction = std::min(fraction, guardFraction(sdfStart, sdfEnd, s, out));
    return fraction;
  }

  void discreteCandidates(const Rigid& worldFromTool, const GodObjectSettings& s, GodObjectStepResult& out) override {
    discreteQuery(worldFromTool, s.sigma + s.contactThreshold);
    out.segmentQueries += m_ccd.stats.segmentQueries;
    for (const PointContact& c : m_ccd.contacts) m_candidates.push_back(c.point);
  }

  void appendContacts(const Rigid& worldFromTool, const GodObjectSettings& s, std::vector<GodObjectContact>& next,
                      GodObjectStepResult& out) override {
    m_candidates.insert(m_candidates.end(), m_contactPoints.begin(), m_contactPoints.end());
    std::sort(m_candidates.begin(), m_candidates.end());
    m_candidates.erase(std::unique(m_candidates.begin(), m_candidates.end()), m_candidates.end());
    for (const int p : m_contactPoints) m_inContact[static_cast<std::size_t>(p)] = 0;
    std::vector<int> kept;
    for (const int p : m_candidates) {
      GodObjectContact c;
      if (!makeContact(worldFromTool, p, c) || !(c.distance - s.sigma <= s.contactThreshold)) continue;
      if (!m_inContact[static_cast<std::size_t>(p)] &&
          std::find(m_contactPoints.begin(), m_contactPoints.end(), p) == m_contactPoints.end())
        ++out.newContacts;
      kept.push_back(p);
      next.push_back(c);
    }
    for (const int p : m_contactPoints) m_notInContact[static_cast<std::size_t>(p)] = 1;
    m_contactPoints.swap(kept);
    for (const int p : m_contactPoints) {
      m_inContact[static_cast<std::size_t>(p)] = 1;
      m_notInContact[static_cast<std::size_t>(p)] = 0;
    }
    m_candidates.clear();
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
    const Rigid at = sdfFromShell(worldFromTool);
    RigidCcdSettings s;
    s.mode = CcdMode::FirstHit;
    s.octree = OctreeMode::Leaves;
    rigidCcd(m_tree, m_field, at, at, s, m_ccd);
    double deepest = 0.0;
    for (const PointContact& c : m_ccd.contacts) deepest = std::max(deepest, -c.depthAtEnd);
    return deepest;
  }

 private:
  Rigid worldFromShell(const Rigid& worldFromTool) const { return m_toolIsShell ? worldFromTool : m_pose; }
  Rigid worldFromField(const Rigid& worldFromTool) const { return m_toolIsShell ? m_pose : worldFromTool; }
  Rigid sdfFromShell(const Rigid& worldFromTool) const {
    return worldFromField(worldFromTool).inverse() * worldFromShell(worldFromTool);
  }

  static RigidCcdSettings querySettings(const GodObjectSettings& s, double sigma) {
    RigidCcdSettings ccd;
    ccd.sigma = sigma;
    ccd.mode = CcdMode::FirstHit;
    ccd.method = s.ccdMethod;
    ccd.octree = s.octree;
    ccd.threads = s.threads;
    return ccd;
  }

  /// The points with phi < level at the pose (a zero-length CCD).
  void discreteQuery(const Rigid& worldFromTool, double level) {
    const Rigid at = sdfFromShell(worldFromTool);
    RigidCcdSettings ccd;
    ccd.sigma = level;
    ccd.mode = CcdMode::FirstHit;
    ccd.octree = OctreeMode::Leaves;
    rigidCcd(m_tree, m_field, at, at, ccd, m_ccd);
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

  /// The ignored points (in contact last cycle) may slide but not sink below slideFloor (god_object.h).
  double guardFraction(const Rigid& sdfStart, const Rigid& sdfEnd, const GodObjectSettings& s,
                       GodObjectStepResult& out) {
    RigidCcdSettings ccd = querySettings(s, s.slideFloor);
    ccd.ignoredPoints = &m_notInContact;
    ccd.useTree = m_contactPoints.size() * 16 > static_cast<std::size_t>(m_tree.pointCount());
    rigidCcd(m_tree, m_field, sdfStart, sdfEnd, ccd, m_ccd);
    out.segmentQueries += m_ccd.stats.segmentQueries;
    double fraction = 1.0;
    SegmentCcdSettings sink;
    sink.mode = CcdMode::FirstHit;
    sink.method = s.ccdMethod;
    sink.octree = s.octree;
    for (const PointContact& c : m_ccd.contacts) {
      if (c.state == SegmentState::Hit) {
        fraction = std::min(fraction, c.fraction);
      } else if (c.state == SegmentState::StartsInside) {  // already under the floor: no deeper than it is
        const Vec3& x = m_tree.shell().positions[static_cast<std::size_t>(c.point)];
        const Vec3 p0 = sdfStart * x;
        const Vec3 p1 = sdfEnd * x;
        sink.sigma = std::min(m_field.distance(p0), s.slideFloor) - s.sinkTolerance;
        m_field.intersectSegment(p0, p1, sink, m_segment);
        ++out.segmentQueries;
        if (m_segment.state == SegmentState::Hit) fraction = std::min(fraction, m_segment.fraction);
      }
    }
    return fraction;
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
  std::vector<std::uint8_t> m_inContact;     // per shell point: in contact last cycle (ignored by the CCD)
  std::vector<std::uint8_t> m_notInContact;  // its complement (the guard CCD's ignore list)
  std::vector<int> m_contactPoints;          // the points in contact now
  std::vector<int> m_candidates;
  RigidCcdResult m_ccd;
  SegmentCcdResult m_segment;
  ContactQueryResult m_query;
};

}  // namespace

ObstacleContacts::ObstacleContacts(const std::vector<HapticObstacle>& obstacles, const PointTree& toolTree,
                                   const GridField* toolField)
    : m_obstacles(obstacles) {
  const double toolRadius = shellRadius(toolTree);
  for (std::size_t i = 0; i < m_obstacles.size(); ++i) {
    const HapticObstacle& o = m_obstacles[i];
    const int index = static_cast<int>(i);
    const std::string name = "obstacle " + std::to_string(i) + (o.name.empty() ? "" : " (" + o.name + ")");
    if (o.shell) {
      if (!toolField) throw Error(name + ": a shell obstacle needs the tool's field (scene key \"shell.field\")");
      m_pairs.push_back(
          std::make_unique<FieldShellPair<GridField>>(index, o.path, toolRadius, *o.shell, *toolField, false));
    } else if (o.grid) {
      m_pairs.push_back(
          std::make_unique<FieldShellPair<GridField>>(index, o.path, toolRadius, toolTree, *o.grid, true));
    } else if (o.plane) {
      m_pairs.push_back(
          std::make_unique<FieldShellPair<PlaneField>>(index, o.path, toolRadius, toolTree, *o.plane, true));
    } else {
      throw Error(name + ": neither a field nor a shell");
    }
  }
}

ObstacleContacts::~ObstacleContacts() = default;

bool ObstacleContacts::anyMoving() const {
  return std::any_of(m_obstacles.begin(), m_obstacles.end(), [](const HapticObstacle& o) { return o.path.moving(); });
}

bool ObstacleContacts::moveTo(double time) {
  bool moved = false;
  for (auto& p : m_pairs) moved = p->moveTo(time) || moved;
  return moved;
}

void ObstacleContacts::moveOver(double time0, double time1) {
  for (auto& p : m_pairs) p->moveOver(time0, time1);
}

Rigid ObstacleContacts::worldFromObstacle(std::size_t i) const {
  return m_pairs.at(i)->pose();
}
std::size_t ObstacleContacts::size() const {
  return m_pairs.size();
}

Rigid ObstacleContacts::push(const Rigid& worldFromTool, const Mat6& mass, const GodObjectSettings& settings,
                             std::vector<GodObjectContact>& contacts, GodObjectStepResult& out) {
  Rigid pose = worldFromTool;
  std::vector<GodObjectContact> rows;
  std::vector<double> bounds(m_pairs.size());
  for (std::size_t i = 0; i < m_pairs.size(); ++i)
    bounds[i] = m_pairs[i]->moveBound(worldFromTool, settings.contactThreshold + settings.sigma);
  // Two rounds: the second sees the normals where the first put the tool (first-order rows are exact only on flat
  // faces).
  for (int round = 0; round < 2; ++round) {
    rows.clear();
    for (std::size_t i = 0; i < m_pairs.size(); ++i)
      m_pairs[i]->nearRows(pose, settings, settings.contactThreshold + bounds[i], rows);
    ConstraintRows j(static_cast<Eigen::Index>(rows.size()), 6);
    Eigen::VectorXd gap(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t k = 0; k < rows.size(); ++k) {
      j.row(static_cast<Eigen::Index>(k)) = contactRow(rows[k].normalIntoObstacle, rows[k].handle);
      gap[static_cast<Eigen::Index>(k)] = rows[k].distance - settings.sigma;
    }
    if (rows.empty() || gap.minCoeff() >= 0.0) break;
    const LeastDistanceResult move = leastDistanceMove(mass, j, gap);
    if (!move.feasible) {  // pinched: no move clears every obstacle; stay
      out.squeezed = true;
      break;
    }
    pose = displacePose(pose, move.move);
  }
  contacts.erase(
      std::remove_if(contacts.begin(), contacts.end(), [](const GodObjectContact& c) { return c.obstacle >= 0; }),
      contacts.end());
  appendContacts(pose, settings, contacts, out);
  return pose;
}

double ObstacleContacts::continuousFraction(const Rigid& start, const Rigid& end, const GodObjectSettings& settings,
                                            GodObjectStepResult& out) {
  double fraction = 1.0;
  for (auto& p : m_pairs) fraction = std::min(fraction, p->continuousFraction(start, end, settings, out));
  return std::clamp(fraction, 0.0, 1.0);
}

void ObstacleContacts::discreteCandidates(const Rigid& worldFromTool, const GodObjectSettings& settings,
                                          GodObjectStepResult& out) {
  for (auto& p : m_pairs) p->discreteCandidates(worldFromTool, settings, out);
}

void ObstacleContacts::appendContacts(const Rigid& worldFromTool, const GodObjectSettings& settings,
                                      std::vector<GodObjectContact>& next, GodObjectStepResult& out) {
  for (auto& p : m_pairs) p->appendContacts(worldFromTool, settings, next, out);
}

void ObstacleContacts::penalty(const ShellMotion& tool, double timestep, const ContactQuerySettings& query,
                               bool consistentGradient, ObstaclePenaltySum& sum) {
  sum = ObstaclePenaltySum{};
  for (auto& p : m_pairs) p->penalty(tool, timestep, query, consistentGradient, sum);
}

double ObstacleContacts::penetration(const Rigid& worldFromTool) {
  double deepest = 0.0;
  for (auto& p : m_pairs) deepest = std::max(deepest, p->penetration(worldFromTool));
  return deepest;
}

}  // namespace sdfccd::haptics
