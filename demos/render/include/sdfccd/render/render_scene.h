/// @file
/// @brief RenderScene: what one offscreen frame shows (bodies at their poses, the ground, point shells, camera).
///
/// @details Validation pictures for headless runs. A scene is plain data: meshes shared by pointer
/// (20 bodies of one bunny share one TriangleMesh), each body's world pose and uniform scale, an optional ground
/// plane y = height with a grid (the simulation's up axis is +y: gravity is (0, -g, 0)), optional point sets
/// coloured by penetration depth so contacts stand out, and an optional camera. Without a camera the renderer
/// frames every body automatically (see render_camera.h).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"
#include "sdfccd/render/render_camera.h"

namespace sdfccd::render {

/// A colour: red, green, blue in [0, 1].
using Color = Eigen::Vector3f;

/// One body: a shared mesh drawn at `worldFromBody` after a uniform scale about the body origin.
struct RenderMesh {
  std::string name;                          ///< shown in error messages
  std::shared_ptr<const TriangleMesh> mesh;  ///< the body's mesh in body coordinates (model units); not null
  Rigid worldFromBody = Rigid::Identity();   ///< the body's pose (m)
  double scale = 1.0;                        ///< uniform scale applied in body coordinates before the pose (> 0)
  Color color = Color(0.80f, 0.55f, 0.35f);  ///< diffuse colour
};

/// A point set (e.g. a body's point shell) in world coordinates, coloured by depth.
///
/// Points with depth <= 0 (or no depths given) are drawn in `color`; points with depth > 0 are contacts and are
/// drawn on a yellow (shallow) to red (at `maxDepth` and beyond) ramp, bigger, and (by default) on top of
/// everything so a contact hidden inside a body still shows where it is.
struct RenderPointSet {
  std::vector<Vec3> pointsInWorld;           ///< positions (m)
  std::vector<double> depths;                ///< empty, or one penetration depth per point (m; > 0 = contact)
  double maxDepth = 0.0;                     ///< depth shown fully red (m); 0 = the largest depth in the set
  Color color = Color(0.25f, 0.45f, 0.95f);  ///< colour of points that are not in contact
  float pointSize = 3.0f;                    ///< diameter of a point (pixels of the output image)
  float contactPointSize = 6.0f;             ///< diameter of a contact point (pixels of the output image)
  bool contactsOnTop = true;                 ///< draw contacts without depth test (visible through bodies)
};

/// The ground: the plane y = height, drawn as a finite square with a grid around the bodies.
struct RenderGround {
  double height = 0.0;       ///< y of the plane (m)
  double gridSpacing = 0.0;  ///< distance between grid lines (m); 0 = chosen from the scene size
  Color color = Color(0.78f, 0.80f, 0.78f);
  Color lineColor = Color(0.45f, 0.47f, 0.45f);
};

/// Everything one frame shows.
struct RenderScene {
  std::vector<RenderMesh> meshes;
  std::optional<RenderGround> ground;  ///< no ground drawn when empty
  std::vector<RenderPointSet> pointSets;
  std::optional<RenderCamera> camera;  ///< explicit camera; empty = automatic framing
};

/// The colour of a point with penetration `depth` (m): `base` when depth <= 0, else a ramp from yellow (shallow)
/// to red (depth >= maxDepth; maxDepth <= 0 counts every contact as fully red).
Color depthColor(double depth, double maxDepth, const Color& base);

/// The world box of every body (transformed vertices, so it is tight). Throws sdfccd::Error for a body
/// without a mesh, an empty mesh, a non-positive or non-finite scale, or a non-finite pose.
Box3 worldBounds(const RenderScene& scene);

/// The world box of one body (same checks as worldBounds).
Box3 worldBounds(const RenderMesh& body);

}  // namespace sdfccd::render
