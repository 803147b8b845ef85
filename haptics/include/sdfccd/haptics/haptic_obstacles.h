/// @file
/// @brief The obstacles of a haptic scene, the one contact source of both haptic methods: one static field at a
/// fixed pose, or several obstacles, each a field or a point shell, static or moving along a scripted pose (paper
/// Section 5).
///
/// @details The scene's single static object is one obstacle with a fixed pose (the fixed-field constructor): the
/// tool's shell against it, with the constraint method's clearance cache and the penalty method's CCD history across
/// ticks (god_object.h, penalty_renderer.h). A scene's "obstacles" list gives one (shell, field) pair per obstacle:
/// - a field obstacle (grid, CSG, mesh or plane) against the tool's point shell;
/// - a shell obstacle against the tool's own field (HapticScene::toolField, in the tool's body frame).
/// An obstacle's pose follows its keyframes (ObstaclePath, interpolated as the user script), so its velocity over a
/// tick is known and every CCD runs on the relative motion of the pair over the tick.
///
/// Forces: the penalty query of a pair gives the wrench on its shell and on its field body; the tool takes the
/// one of its own role, about its centre of mass (the origin of its body frame): for a shell obstacle that is minus
/// the force on the obstacle's points, and the torque of those reactions about the tool's centre.
///
/// Constraint method (god_object.h): the god-object's rows are one per point in contact, [n, r x n] with n the
/// direction the tool must not move along and r from the tool's centre to the point, in both roles:
/// - tool point against an obstacle field: n = -grad(phi_obstacle) (into the obstacle), r = tool point - centre;
/// - obstacle point against the tool field: n = +grad(phi_tool) (the tool's outward normal: moving along it would
///   swallow the point), r = obstacle point - centre.
/// Moving obstacles are an operator split of each simulation cycle: first the obstacles jump to their pose at the
/// cycle's time and push the god-object out of the way (the least-distance move, in the QP's mass metric, that puts
/// every point near an obstacle back on its contact level set: min ||p||_M subject to n_k . (p at r_k) <=
/// phi_k - sigma, least_distance.h); then the usual cycle runs against the obstacles held at that pose. The push's
/// constraints are the first-order ones of the pair (exact for flat faces); the contact threshold widened by the
/// obstacle's move this cycle makes sure every point it can reach is in the set.
///
/// Thread safety: one ObstacleContacts per renderer, which owns it (it keeps each pair's contact state and scratch).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/haptics/spatial_types.h"
#include "sdfccd/haptics/user_script.h"
#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"
#include "sdfccd/response/contact_query.h"
#include "sdfccd/shell/point_tree.h"

namespace sdfccd::haptics {

struct GodObjectSettings;
struct GodObjectContact;
struct GodObjectStepResult;
struct PenaltyRendererSettings;

/// An obstacle's pose over time: fixed, or keyframes (linear positions, slerped orientations, held before the
/// first and after the last key).
struct ObstaclePath {
  Rigid worldFromObstacle = Rigid::Identity();  ///< the pose when there are no keys
  std::optional<UserScript> keys;

  Rigid poseAt(double time) const { return keys ? keys->targetAt(time) : worldFromObstacle; }
  bool moving() const { return keys && keys->keys().size() > 1; }
};

/// One obstacle: a field (grid or plane) or a point shell, in its own frame.
struct HapticObstacle {
  std::string name;
  std::shared_ptr<const GridField> grid;     ///< a grid field obstacle (CSG or mesh)
  std::optional<PlaneField> plane;           ///< an analytic plane
  std::shared_ptr<const PointTree> shell;    ///< a shell obstacle (against the tool's field)
  std::shared_ptr<const TriangleMesh> mesh;  ///< the mesh a shell was sampled from (drawing)
  double cellSize = 0.0;                     ///< the field's spacing, or a nominal cell (model units)
  ObstaclePath path;

  bool isShell() const { return shell != nullptr; }
};

/// One pair's contact gathering (a field obstacle against the tool's shell, or a shell obstacle against the
/// tool's field). Internal to the library (contact/obstacle_pair.h).
class ObstaclePair;

/// The penalty method's contact state summed over the obstacles for one tick.
struct ObstaclePenaltySum {
  Vec6 wrenchOnTool = Vec6::Zero();  ///< N, N m about the tool's centre, world
  Mat6 gradient = Mat6::Zero();      ///< d(wrench on the tool) / d(tool pose) at the end pose
  int contactCount = 0;
  double maxPenetration = 0.0;  ///< model units
  std::int64_t segmentQueries = 0;
  std::int64_t certifiedNodes = 0;  ///< the fixed field's CCD history: tree nodes ruled out by their certificate
};

/// The obstacles of a scene against one tool (see the file comment).
class ObstacleContacts {
 public:
  /// `toolTree`: the tool's shell (body frame, origin at the centre of mass); `toolField`: the tool's field in
  /// the same frame (null: shell obstacles are an error); both must outlive this object. The obstacles are copied
  /// (their fields and shells are shared). Throws sdfccd::Error on an obstacle with neither a field nor a shell,
  /// or a shell obstacle without a tool field.
  ObstacleContacts(const std::vector<HapticObstacle>& obstacles, const PointTree& toolTree, const GridField* toolField);
  /// One static field at a fixed pose (`worldFromField`) against the tool's shell `toolTree` (body frame, origin at
  /// the centre of mass); both must outlive this object. Defined for the field types of field_interface.h. Throws
  /// sdfccd::Error on a non-finite pose.
  template <class Field>
  ObstacleContacts(const PointTree& toolTree, const Field& field, const Rigid& worldFromField);
  ~ObstacleContacts();
  ObstacleContacts(ObstacleContacts&&) noexcept;
  ObstacleContacts& operator=(ObstacleContacts&&) noexcept;
  ObstacleContacts(const ObstacleContacts&) = delete;
  ObstacleContacts& operator=(const ObstacleContacts&) = delete;

  /// Readies the pairs for the renderer that owns this object: the constraint method with `settings`, or the penalty
  /// method with `settings`, its contact query and the tool's start pose.
  void prepare(const GodObjectSettings& settings);
  void prepare(const PenaltyRendererSettings& settings, const ContactQuerySettings& query,
               const Rigid& worldFromToolStart);

  /// Moves every obstacle to its pose at `time` (s); returns true when one of them moved.
  bool moveTo(double time);
  /// The obstacles over [time0, time1] (penalty method: the tick's motion, with its velocities).
  void moveOver(double time0, double time1);
  Rigid worldFromObstacle(std::size_t i) const;
  std::size_t size() const;
  /// True when an obstacle moves along a path.
  bool anyMoving() const;

  // --- Constraint method (god_object.h), with the obstacles held at their present pose. ---
  /// The move that pushes the tool out of the obstacles' way after they moved (see the file comment); returns the
  /// pushed pose. `contacts` is replaced by the contact set there.
  Rigid push(const Rigid& worldFromTool, const Mat6& mass, const GodObjectSettings& settings,
             std::vector<GodObjectContact>& contacts, GodObjectStepResult& out);
  /// Step 5: the earliest contact fraction of the tool's move start -> end against every obstacle (points in
  /// contact ignored, the guard CCD on them); collects each pair's candidates.
  double continuousFraction(const Rigid& start, const Rigid& end, const GodObjectSettings& settings,
                            GodObjectStepResult& out);
  /// The discrete variant: every point near an obstacle at the pose becomes a candidate.
  void discreteCandidates(const Rigid& worldFromTool, const GodObjectSettings& settings, GodObjectStepResult& out);
  /// Step 6: appends each pair's contacts at the pose (its candidates and its last contacts) to `next`.
  void appendContacts(const Rigid& worldFromTool, const GodObjectSettings& settings,
                      std::vector<GodObjectContact>& next, GodObjectStepResult& out);

  // --- Penalty method (penalty_renderer.h), over the motion set by moveOver(). ---
  /// Every pair's penalty query over the tool's motion; the wrench on the tool and its pose gradient at the end.
  void penalty(const ShellMotion& tool, double timestep, const ContactQuerySettings& query, bool consistentGradient,
               ObstaclePenaltySum& sum);

  /// The deepest penetration (phi < 0) of any pair at the tool's pose (model units, >= 0).
  double penetration(const Rigid& worldFromTool);

 private:
  std::vector<HapticObstacle> m_obstacles;  // the pairs refer to these: declared first, destroyed last
  std::vector<std::unique_ptr<ObstaclePair>> m_pairs;
};

}  // namespace sdfccd::haptics
