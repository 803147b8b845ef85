/// @file
/// @brief ObstaclePair: one obstacle against the tool, the unit an ObstacleContacts gathers its contacts from, and
/// what the two kinds of pair share (internal to the haptics library).
///
/// @details The kinds:
/// - the fixed field (fixed_field_pair.cpp): one static field at a fixed pose against the tool's shell, the scene's
///   single static object, with the constraint method's clearance cache (clearance_cache.h) and the penalty
///   method's CCD history across ticks (rigid_ccd_coherence.h);
/// - the field-shell pair (field_shell_pair.cpp): an obstacle of a scene's "obstacles" list, static or moving, a
///   field against the tool's shell or a shell against the tool's field.
/// Both keep their constraint contacts in a PairContacts (pair_contacts.h) and share the penetration probe.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/ccd/segment_ccd.h"
#include "sdfccd/haptics/god_object.h"
#include "sdfccd/haptics/haptic_obstacles.h"
#include "sdfccd/haptics/penalty_renderer.h"
#include "sdfccd/math_types.h"
#include "sdfccd/response/contact_query.h"
#include "sdfccd/shell/point_tree.h"

namespace sdfccd::haptics {

/// One obstacle against the tool (see haptic_obstacles.h): its pose along its path, and the contact queries of
/// both methods.
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

  /// Readies the pair for the constraint method with these settings (per-point state, caches).
  virtual void prepareConstraint(const GodObjectSettings& /*settings*/) {}
  /// Readies the pair for the penalty method: `query` is the renderer's, the tool starts at `worldFromToolStart`.
  virtual void preparePenalty(const ContactQuerySettings& /*query*/, const PenaltyRendererSettings& /*settings*/,
                              const Rigid& /*worldFromToolStart*/) {}

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

/// The cross-product matrix [v]x (so that [v]x w = v x w).
inline Mat3 crossMatrix(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// The settings of the constraint method's CCD queries at level set `sigma` (first hits).
inline RigidCcdSettings constraintCcdSettings(const GodObjectSettings& s, double sigma) {
  RigidCcdSettings ccd;
  ccd.sigma = sigma;
  ccd.mode = CcdMode::FirstHit;
  ccd.method = s.ccdMethod;
  ccd.octree = s.octree;
  ccd.threads = s.threads;
  return ccd;
}

/// The deepest penetration (phi < 0) of any shell point at the pose `sdfFromShell` (model units, >= 0): a point
/// query of the tree.
template <class Field>
double deepestPenetration(const PointTree& tree, const Field& field, const Rigid& sdfFromShell,
                          RigidCcdResult& scratch) {
  RigidCcdSettings s;
  s.sigma = 0.0;
  s.mode = CcdMode::FirstHit;
  s.octree = OctreeMode::Leaves;
  rigidCcd(tree, field, sdfFromShell, sdfFromShell, s, scratch);
  double deepest = 0.0;
  for (const PointContact& c : scratch.contacts) deepest = std::max(deepest, -c.depthAtEnd);
  return deepest;
}

/// The fixed field (fixed_field_pair.cpp): `field` at `worldFromField` against the tool's shell `tree` (both must
/// outlive the pair). Defined for the field types of field_interface.h.
template <class Field>
std::unique_ptr<ObstaclePair> makeFixedFieldPair(const PointTree& tree, const Field& field,
                                                 const Rigid& worldFromField);

/// A field-shell pair (field_shell_pair.cpp): the tool's shell against an obstacle's field (toolIsShell), or an
/// obstacle's shell against the tool's field. `tree` and `field` must outlive the pair.
std::unique_ptr<ObstaclePair> makeFieldShellPair(int index, const ObstaclePath& path, double toolRadius,
                                                 const PointTree& tree, const GridField& field, bool toolIsShell);
std::unique_ptr<ObstaclePair> makeFieldShellPair(int index, const ObstaclePath& path, double toolRadius,
                                                 const PointTree& tree, const PlaneField& field, bool toolIsShell);

}  // namespace sdfccd::haptics
