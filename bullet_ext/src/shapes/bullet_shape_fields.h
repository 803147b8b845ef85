/// @file
/// @brief Every Bullet shape that is not ours, as what our contact needs: a field (for our shell to meet) and,
/// for convex shapes, a point shell (for our field to meet). Private to sdfccd::bullet (beyond the paper; see
/// ContactSystem).
///
/// @details Which shape becomes what (ShapeKind):
/// - Plane and AnalyticConvex (btStaticPlaneShape; btBoxShape, btSphereShape, btCapsuleShape): closed-form
///   fields and shells (convex_fields.h, roles/convex_shells.cpp);
/// - Convex: every other btConvexShape (cylinder and cone: exact fields of revolution, revolvedField(); convex hull,
/// multi-sphere, convex triangle mesh, point
///   cloud, ...): its margin-free support points (a hull's or point cloud's own points; otherwise the support
///   function in 518 directions) made a convex hull (btConvexHullComputer), grown by Bullet's collision margin
///   (a multi-sphere or a wrapper: the support with the margin, not grown; see grownByMargin()):
///   a ConvexPolytopeField, and points sampled on that surface. Both are cached by the support points' content
///   (not the shape's address, which a freed shape hands on), the margin and the spacing;
/// - Mesh: static triangle meshes and terrain (btBvhTriangleMeshShape, btScaledBvhTriangleMeshShape,
///   btHeightfieldTerrainShape, btGImpactMeshShape, btMultimaterialTriangleMeshShape): each step, the triangles
///   in the box our body sweeps (the mesh's own BVH, processAllTriangles) become a TriangleSetField, one-sided
///   towards our body's centre with a thickness of half its thinnest size: a 1 km level costs only the
///   triangles near the body;
/// - Unsupported: the rest (soft bodies, btSdfCollisionShape, user shapes): announced and counted.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sdfccd/field/polytope_fields.h"
#include "sdfccd/math_types.h"
#include "sdfccd/shell/point_tree.h"

class btCollisionAlgorithmCreateFunc;
class btCollisionDispatcher;
class btCollisionShape;
class btConvexShape;

namespace sdfccd::bullet::detail {

enum class ShapeKind : std::uint8_t { Ours, Plane, AnalyticConvex, Convex, Mesh, Unsupported };

/// What our contact makes of `shape` (see the file comment).
ShapeKind shapeKind(const btCollisionShape* shape);
/// Registers (ours, X) and (X, ours), contacts and closest points: our algorithm for every X but compounds
/// (Bullet's own compound algorithms, from the dispatcher's configuration, which split a compound into its
/// children and dispatch each child pair back here) and btEmptyShape (`empty`: nothing to collide).
void registerOurPairs(btCollisionDispatcher& dispatcher, int ours, btCollisionAlgorithmCreateFunc* contacts,
                      btCollisionAlgorithmCreateFunc* closest, btCollisionAlgorithmCreateFunc* empty);

/// The convex shapes' fields and shells, cached (see the file comment). Not thread safe: used on the stepping
/// thread only (roles with these shapes are never in the parallel batch, deferred_queries.h).
/// Lookups go first by the shape's address, checked against a fingerprint (type, margin, scaling, and a hull's
/// or point cloud's points, or the support points in 14 directions): a pair-step costs that, not the 518
/// support points of the content key; an address a freed shape hands on to a different shape fails the check
/// (a new shape whose fingerprint matches in every one of these is taken for the old one). Entries unused for
/// evictIdle's idle steps are dropped.
class ConvexShapeCache {
 public:
  ConvexShapeCache();
  ~ConvexShapeCache();
  ConvexShapeCache(const ConvexShapeCache&) = delete;
  ConvexShapeCache& operator=(const ConvexShapeCache&) = delete;

  /// The field of a Convex shape, in its own frame; null when its hull is degenerate (flat, a segment or a
  /// point: no volume), which the caller treats as an unsupported pair.
  const ConvexPolytopeField* field(const btConvexShape* shape);
  /// Points on its surface at about `spacing` (at most `maxPoints`: the spacing grows), with the margin; null
  /// as field().
  const PointTree* shell(const btConvexShape* shape, double spacing, int maxPoints);
  /// The smallest size of its box (with the margin; m): the shell spacing's upper bound works from it.
  double thinnestExtent(const btConvexShape* shape);
  /// Once per step: `now` is the step's number; entries and addresses unused for more than `idleSteps` go.
  void evictIdle(std::int64_t now, std::int64_t idleSteps);
  std::size_t size() const { return m_entries.size(); }  ///< cached hulls

 private:
  struct Entry;
  struct Recent {
    std::vector<double> fingerprint;
    Entry* entry = nullptr;
    std::int64_t lastUse = 0;
  };
  Entry& entry(const btConvexShape* shape);
  Entry& entryByContent(const btConvexShape* shape);  // the 518 support points' key

  std::map<std::string, std::unique_ptr<Entry>> m_entries;  // by support points, margin
  std::map<const btConvexShape*, Recent> m_recent;          // by address, checked by fingerprint
  std::int64_t m_now = 0;
};

/// The triangles of a Mesh shape that overlap `boxInShape` (three vertices each, its frame, scaling applied).
void meshTriangles(const btCollisionShape* shape, const Box3& boxInShape, std::vector<Vec3>& outVertices,
                   std::vector<TriangleIndices>& outTriangles);

/// A btCylinderShape (X/Y/Z) or btConeShape (X/Y/Z) as its exact field (RevolvedConvexField: margin-free sizes
/// grown by the margin; a cylinder scaled unevenly across its axis takes its first radial half extent);
/// nothing for any other shape, whose field is its hull's (ConvexShapeCache::field).
std::optional<RevolvedConvexField> revolvedField(const btCollisionShape* shape);

/// The triangles of a Mesh shape inside `boxInShape` (its own frame, scaling applied) as a field grown by the
/// shape's margin, one-sided towards `outside` with `thickness` (TriangleSetField); nothing when the box holds
/// no triangle.
std::optional<TriangleSetField> meshTrianglesInBox(const btCollisionShape* shape, const Box3& boxInShape,
                                                   double thickness, const Vec3& outside);

}  // namespace sdfccd::bullet::detail
