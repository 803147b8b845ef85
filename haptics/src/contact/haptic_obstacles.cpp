/// @file
/// @brief ObstacleContacts: every obstacle's pair with the tool, for both haptic methods (see haptic_obstacles.h);
/// the pairs are in obstacle_pair.h.
#include "sdfccd/haptics/haptic_obstacles.h"

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "contact/obstacle_pair.h"
#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/haptics/god_object.h"
#include "sdfccd/haptics/least_distance.h"
#include "sdfccd/haptics/rigid_body_state.h"

namespace sdfccd::haptics {

namespace {

/// The largest |x| over a shell's points (its radius about its frame's origin).
double shellRadius(const PointTree& tree) {
  double r = 0.0;
  for (const Vec3& p : tree.shell().positions) r = std::max(r, p.norm());
  return r;
}

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
      m_pairs.push_back(makeFieldShellPair(index, o.path, toolRadius, *o.shell, *toolField, false));
    } else if (o.grid) {
      m_pairs.push_back(makeFieldShellPair(index, o.path, toolRadius, toolTree, *o.grid, true));
    } else if (o.plane) {
      m_pairs.push_back(makeFieldShellPair(index, o.path, toolRadius, toolTree, *o.plane, true));
    } else {
      throw Error(name + ": neither a field nor a shell");
    }
  }
}

template <class Field>
ObstacleContacts::ObstacleContacts(const PointTree& toolTree, const Field& field, const Rigid& worldFromField) {
  if (!worldFromField.matrix().allFinite()) throw Error("obstacle: non-finite pose");
  m_pairs.push_back(makeFixedFieldPair(toolTree, field, worldFromField));
}

#define SDFCCD_INSTANTIATE_FIXED_OBSTACLE(Field) \
  template ObstacleContacts::ObstacleContacts(const PointTree&, const Field&, const Rigid&);
SDFCCD_FOR_EACH_FIELD(SDFCCD_INSTANTIATE_FIXED_OBSTACLE)
#undef SDFCCD_INSTANTIATE_FIXED_OBSTACLE

ObstacleContacts::ObstacleContacts(ObstacleContacts&&) noexcept = default;
ObstacleContacts& ObstacleContacts::operator=(ObstacleContacts&&) noexcept = default;

ObstacleContacts::~ObstacleContacts() = default;

void ObstacleContacts::prepare(const GodObjectSettings& settings) {
  for (auto& p : m_pairs) p->prepareConstraint(settings);
}

void ObstacleContacts::prepare(const PenaltyRendererSettings& settings, const ContactQuerySettings& query,
                               const Rigid& worldFromToolStart) {
  for (auto& p : m_pairs) p->preparePenalty(query, settings, worldFromToolStart);
}

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
  contacts.clear();  // every contact is an obstacle's: the pairs' contacts at the pushed pose replace them
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
