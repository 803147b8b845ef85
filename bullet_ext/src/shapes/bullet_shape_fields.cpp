/// @file
/// @brief Bullet's other shapes as fields and shells (see bullet_shape_fields.h): classification, the convex
/// hull of a convex shape's support points, its surface points, and the triangles of a mesh near a body.
#include "shapes/bullet_shape_fields.h"

#include <BulletCollision/BroadphaseCollision/btBroadphaseProxy.h>
#include <BulletCollision/CollisionDispatch/btCollisionConfiguration.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionShapes/btConcaveShape.h>
#include <BulletCollision/CollisionShapes/btConeShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btConvexPointCloudShape.h>
#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btTriangleCallback.h>
#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <vector>

#include "common/bullet_conversions.h"
#include "shapes/convex_fields.h"
#include "sdfccd/bullet/sdfccd_shape.h"

namespace sdfccd::bullet::detail {
namespace {

constexpr int kSupportDirections = 512;  // support-function samples of a shape without its own point list

/// Directions spread evenly over the sphere (a Fibonacci spiral), the same every call.
const std::vector<Vec3>& supportDirections() {
  static const std::vector<Vec3> directions = [] {
    std::vector<Vec3> out;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < kSupportDirections; ++i) {
      const double y = 1.0 - 2.0 * (i + 0.5) / kSupportDirections;
      const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
      out.emplace_back(r * std::cos(golden * i), y, r * std::sin(golden * i));
    }
    // The six axis directions too: a cylinder's or cone's caps and tips are then exact.
    for (int axis = 0; axis < 3; ++axis) {
      out.push_back(Vec3::Unit(axis));
      out.push_back(-Vec3::Unit(axis));
    }
    return out;
  }();
  return directions;
}

/// Shapes whose Bullet surface is their margin-free support points' hull grown by the margin (a Minkowski sum
/// with a ball): the hull is then exact, its rounding too. For the others (a btMultiSphereShape, whose
/// margin-free support is its spheres shrunk by the margin, inside out when the margin exceeds a radius; a
/// wrapper, a user's shape) only the support with the margin is the shape's: its hull, not grown.
bool grownByMargin(int shapeType) {
  return shapeType == CONVEX_HULL_SHAPE_PROXYTYPE || shapeType == CONVEX_POINT_CLOUD_SHAPE_PROXYTYPE ||
         shapeType == CONVEX_TRIANGLEMESH_SHAPE_PROXYTYPE || shapeType == CYLINDER_SHAPE_PROXYTYPE ||
         shapeType == CONE_SHAPE_PROXYTYPE || shapeType == TRIANGLE_SHAPE_PROXYTYPE;
}

/// The shape's support points (scaling applied), margin-free where grownByMargin (its own points where it has a
/// list), with the margin otherwise.
std::vector<Vec3> supportPoints(const btConvexShape* shape) {
  std::vector<Vec3> points;
  if (shape->getShapeType() == CONVEX_HULL_SHAPE_PROXYTYPE) {
    const auto* hull = static_cast<const btConvexHullShape*>(shape);
    for (int i = 0; i < hull->getNumPoints(); ++i) points.push_back(toVec3(hull->getScaledPoint(i)));
  } else if (shape->getShapeType() == CONVEX_POINT_CLOUD_SHAPE_PROXYTYPE) {
    const auto* cloud = static_cast<const btConvexPointCloudShape*>(shape);
    for (int i = 0; i < cloud->getNumPoints(); ++i) points.push_back(toVec3(cloud->getScaledPoint(i)));
  } else {
    const bool grown = grownByMargin(shape->getShapeType());
    for (const Vec3& d : supportDirections()) {
      points.push_back(toVec3(grown ? shape->localGetSupportingVertexWithoutMargin(toBt(d))
                                    : shape->localGetSupportingVertex(toBt(d))));
    }
  }
  return points;
}

/// The convex hull of `points` as outward triangles; false when it has no volume.
bool hullTriangles(const std::vector<Vec3>& points, std::vector<Vec3>& outVertices,
                   std::vector<TriangleIndices>& outTriangles, std::vector<std::vector<int>>& outFaces) {
  std::vector<double> coords;
  for (const Vec3& p : points) coords.insert(coords.end(), {p.x(), p.y(), p.z()});
  btConvexHullComputer hull;
  hull.compute(coords.data(), 3 * static_cast<int>(sizeof(double)), static_cast<int>(points.size()), 0, 0);
  if (hull.vertices.size() < 4 || hull.faces.size() < 4) return false;
  outVertices.clear();
  outTriangles.clear();
  outFaces.clear();
  Vec3 centre = Vec3::Zero();
  for (int i = 0; i < hull.vertices.size(); ++i) {
    outVertices.push_back(toVec3(hull.vertices[i]));
    centre += outVertices.back();
  }
  centre /= double(outVertices.size());
  for (int f = 0; f < hull.faces.size(); ++f) {
    std::vector<int> loop;
    const btConvexHullComputer::Edge* first = &hull.edges[hull.faces[f]];
    const btConvexHullComputer::Edge* e = first;
    do {
      loop.push_back(e->getTargetVertex());
      e = e->getNextEdgeOfFace();
    } while (e != first && loop.size() < 100000);
    bool flip = false;
    for (std::size_t k = 1; k + 1 < loop.size(); ++k) {  // a fan over the (convex, planar) face
      TriangleIndices t{loop[0], loop[k], loop[k + 1]};
      const Vec3& a = outVertices[static_cast<std::size_t>(t[0])];
      const Vec3 n =
          (outVertices[static_cast<std::size_t>(t[1])] - a).cross(outVertices[static_cast<std::size_t>(t[2])] - a);
      if (!(n.norm() > 1e-14 * (1.0 + a.squaredNorm()))) continue;
      flip = n.dot(a - centre) < 0.0;  // outward, whatever the computer's winding
      if (flip) std::swap(t[1], t[2]);
      outTriangles.push_back(t);
    }
    if (flip) std::reverse(loop.begin(), loop.end());
    outFaces.push_back(loop);
  }
  // No volume: every vertex on one plane.
  const Vec3& a = outVertices[static_cast<std::size_t>(outTriangles.empty() ? 0 : outTriangles[0][0])];
  if (outTriangles.size() < 4) return false;
  const Vec3 n = (outVertices[static_cast<std::size_t>(outTriangles[0][1])] - a)
                     .cross(outVertices[static_cast<std::size_t>(outTriangles[0][2])] - a)
                     .normalized();
  double thickness = 0.0;
  for (const Vec3& v : outVertices) thickness = std::max(thickness, std::abs(n.dot(v - a)));
  return thickness > 1e-9 * (1.0 + a.norm());
}

/// Points on a convex polytope's surface at about `spacing`, pushed out by `radius` along their normals: a
/// square grid in each face's plane (its own normal), points along each edge (the two faces' normals averaged)
/// and the vertices (the incident faces' normals averaged); each with area A / N.
PointShell sampleGrownSurface(const std::vector<Vec3>& v, const std::vector<std::vector<int>>& faces, double radius,
                              double spacing) {
  PointShell shell;
  double area = 0.0;
  std::vector<Vec3> faceNormals;
  std::map<std::pair<int, int>, Vec3> edgeNormals;  // by (smaller, larger) vertex: the two faces' normals summed
  std::vector<Vec3> vertexNormals(v.size(), Vec3::Zero());
  for (const std::vector<int>& loop : faces) {
    Vec3 newell = Vec3::Zero();  // twice the polygon's area vector
    for (std::size_t k = 0; k < loop.size(); ++k) {
      newell += v[static_cast<std::size_t>(loop[k])].cross(v[static_cast<std::size_t>(loop[(k + 1) % loop.size()])]);
    }
    area += 0.5 * newell.norm();
    const Vec3 n = newell.norm() > 0.0 ? Vec3(newell.normalized()) : Vec3::Zero();  // zero: a sliver of no area
    faceNormals.push_back(n);
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];
      edgeNormals.try_emplace({std::min(a, b), std::max(a, b)}, Vec3::Zero()).first->second += n;  // Eigen: no zero
      vertexNormals[static_cast<std::size_t>(a)] += n;
    }
  }
  auto add = [&](const Vec3& p, const Vec3& n) {
    shell.positions.push_back(p + radius * n);
    shell.normals.push_back(n);
  };
  for (std::size_t f = 0; f < faces.size(); ++f) {  // the faces' interiors: a grid in the face's plane
    const Vec3& n = faceNormals[f];
    if (n.isZero()) continue;
    const Vec3 u = n.unitOrthogonal();
    const Vec3 w = n.cross(u);
    std::vector<Eigen::Vector2d> polygon;
    Eigen::AlignedBox2d box;
    for (int i : faces[f]) {
      polygon.emplace_back(u.dot(v[static_cast<std::size_t>(i)]), w.dot(v[static_cast<std::size_t>(i)]));
      box.extend(polygon.back());
    }
    const double height = n.dot(v[static_cast<std::size_t>(faces[f][0])]);
    const double margin = 0.5 * spacing;  // keep clear of the edges, which have their own points
    for (double x = std::ceil(box.min().x() / spacing) * spacing; x <= box.max().x(); x += spacing) {
      for (double y = std::ceil(box.min().y() / spacing) * spacing; y <= box.max().y(); y += spacing) {
        bool inside = true;  // counter-clockwise convex polygon: left of every edge by the margin
        for (std::size_t k = 0; k < polygon.size() && inside; ++k) {
          const Eigen::Vector2d e = polygon[(k + 1) % polygon.size()] - polygon[k];
          const Eigen::Vector2d r = Eigen::Vector2d(x, y) - polygon[k];
          inside = e.x() * r.y() - e.y() * r.x() >= margin * e.norm();
        }
        if (inside) add(x * u + y * w + height * n, n);
      }
    }
  }
  for (const auto& [edge, normalSum] : edgeNormals) {  // the edges, their ends excluded
    const Vec3& a = v[static_cast<std::size_t>(edge.first)];
    const Vec3& b = v[static_cast<std::size_t>(edge.second)];
    if (!(normalSum.norm() > 1e-9)) continue;
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing)));
    for (int i = 1; i < steps; ++i) add(a + (b - a) * (double(i) / steps), normalSum.normalized());
  }
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (vertexNormals[i].norm() > 1e-9) add(v[i], vertexNormals[i].normalized());
  }
  assignUniformAreas(shell, area);
  return shell;
}

/// Collects the triangles processAllTriangles hands over (three vertices each, shape frame).
class TriangleCollector : public btTriangleCallback {
 public:
  void processTriangle(btVector3* triangle, int, int) override {
    const int base = static_cast<int>(vertices.size());
    for (int i = 0; i < 3; ++i) vertices.push_back(toVec3(triangle[i]));
    triangles.push_back({base, base + 1, base + 2});
  }
  std::vector<Vec3> vertices;
  std::vector<TriangleIndices> triangles;
};

}  // namespace

ShapeKind shapeKind(const btCollisionShape* shape) {
  if (isSdfccdShape(shape)) return ShapeKind::Ours;
  const int type = shape->getShapeType();
  if (type == STATIC_PLANE_PROXYTYPE) return ShapeKind::Plane;
  if (isSupportedConvexType(type)) return ShapeKind::AnalyticConvex;
  if (shape->isConvex()) return ShapeKind::Convex;
  switch (type) {
    case TRIANGLE_MESH_SHAPE_PROXYTYPE:
    case SCALED_TRIANGLE_MESH_SHAPE_PROXYTYPE:
    case TERRAIN_SHAPE_PROXYTYPE:
    case GIMPACT_SHAPE_PROXYTYPE:
    case MULTIMATERIAL_TRIANGLE_MESH_PROXYTYPE:
      return ShapeKind::Mesh;
    default:
      return ShapeKind::Unsupported;
  }
}

void registerOurPairs(btCollisionDispatcher& dispatcher, int ours, btCollisionAlgorithmCreateFunc* contacts,
                      btCollisionAlgorithmCreateFunc* closest, btCollisionAlgorithmCreateFunc* empty) {
  btCollisionConfiguration* configuration = dispatcher.getCollisionConfiguration();
  for (int other = 0; other < MAX_BROADPHASE_COLLISION_TYPES; ++other) {
    btCollisionAlgorithmCreateFunc* forward = contacts;
    btCollisionAlgorithmCreateFunc* backward = contacts;
    btCollisionAlgorithmCreateFunc* forwardClosest = closest;
    btCollisionAlgorithmCreateFunc* backwardClosest = closest;
    if (other == COMPOUND_SHAPE_PROXYTYPE && configuration != nullptr) {
      forward = configuration->getCollisionAlgorithmCreateFunc(ours, other);
      backward = configuration->getCollisionAlgorithmCreateFunc(other, ours);
      forwardClosest = configuration->getClosestPointsAlgorithmCreateFunc(ours, other);
      backwardClosest = configuration->getClosestPointsAlgorithmCreateFunc(other, ours);
    } else if (other == COMPOUND_SHAPE_PROXYTYPE || other == EMPTY_SHAPE_PROXYTYPE) {
      forward = backward = forwardClosest = backwardClosest = empty;
    }
    dispatcher.registerCollisionCreateFunc(ours, other, forward);
    dispatcher.registerCollisionCreateFunc(other, ours, backward);
    dispatcher.registerClosestPointsCreateFunc(ours, other, forwardClosest);
    dispatcher.registerClosestPointsCreateFunc(other, ours, backwardClosest);
  }
}

struct ConvexShapeCache::Entry {
  std::int64_t lastUse = 0;                    // evictIdle's step
  std::unique_ptr<ConvexPolytopeField> field;  // null: degenerate hull
  std::vector<std::vector<int>> faces;         // the hull's faces: outward loops of field->vertices()
  Box3 box;                                    // with the margin
  std::map<std::pair<double, int>, std::unique_ptr<PointTree>> shells;  // by spacing, cap
};

ConvexShapeCache::ConvexShapeCache() = default;
ConvexShapeCache::~ConvexShapeCache() = default;

namespace {

/// What tells a shape at a known address from another one there (see ConvexShapeCache): its type, margin and
/// scaling, and a hull's or point cloud's own points, or else its support points in the 6 axis and 8 diagonal
/// directions (with the margin).
std::vector<double> convexFingerprint(const btConvexShape* shape) {
  const btVector3 scaling = shape->getLocalScaling();
  std::vector<double> f = {double(shape->getShapeType()), double(shape->getMargin()), double(scaling.x()),
                           double(scaling.y()), double(scaling.z())};
  auto add = [&f](const btVector3& p) { f.insert(f.end(), {double(p.x()), double(p.y()), double(p.z())}); };
  if (shape->getShapeType() == CONVEX_HULL_SHAPE_PROXYTYPE) {
    const auto* hull = static_cast<const btConvexHullShape*>(shape);
    for (int i = 0; i < hull->getNumPoints(); ++i) add(hull->getScaledPoint(i));
  } else if (shape->getShapeType() == CONVEX_POINT_CLOUD_SHAPE_PROXYTYPE) {
    const auto* cloud = static_cast<const btConvexPointCloudShape*>(shape);
    for (int i = 0; i < cloud->getNumPoints(); ++i) add(cloud->getScaledPoint(i));
  } else {
    for (int axis = 0; axis < 3; ++axis) {
      for (const btScalar sign : {btScalar(1), btScalar(-1)}) {
        btVector3 d(0, 0, 0);
        d[axis] = sign;
        add(shape->localGetSupportingVertex(d));
      }
    }
    for (int corner = 0; corner < 8; ++corner) {
      add(shape->localGetSupportingVertex(btVector3(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1)));
    }
  }
  return f;
}

}  // namespace

void ConvexShapeCache::evictIdle(std::int64_t now, std::int64_t idleSteps) {
  m_now = now;
  for (auto it = m_recent.begin(); it != m_recent.end();) {
    it = it->second.lastUse + idleSteps < now ? m_recent.erase(it) : std::next(it);
  }
  // An entry is used whenever an address that leads to it is, so its addresses went above.
  for (auto it = m_entries.begin(); it != m_entries.end();) {
    it = it->second->lastUse + idleSteps < now ? m_entries.erase(it) : std::next(it);
  }
}

ConvexShapeCache::Entry& ConvexShapeCache::entry(const btConvexShape* shape) {
  std::vector<double> fingerprint = convexFingerprint(shape);
  const auto recent = m_recent.find(shape);
  if (recent != m_recent.end() && recent->second.fingerprint == fingerprint) {
    recent->second.lastUse = m_now;
    recent->second.entry->lastUse = m_now;
    return *recent->second.entry;
  }
  Entry& found = entryByContent(shape);
  found.lastUse = m_now;
  m_recent[shape] = Recent{std::move(fingerprint), &found, m_now};
  return found;
}

ConvexShapeCache::Entry& ConvexShapeCache::entryByContent(const btConvexShape* shape) {
  const std::vector<Vec3> points = supportPoints(shape);
  const double margin = grownByMargin(shape->getShapeType()) ? double(shape->getMargin()) : 0.0;
  std::string key(reinterpret_cast<const char*>(points.data()), points.size() * sizeof(Vec3));
  key.append(reinterpret_cast<const char*>(&margin), sizeof(margin));
  std::unique_ptr<Entry>& slot = m_entries[key];
  if (slot) return *slot;
  slot = std::make_unique<Entry>();
  std::vector<Vec3> vertices;
  std::vector<TriangleIndices> triangles;
  if (hullTriangles(points, vertices, triangles, slot->faces)) {
    for (const Vec3& p : vertices) slot->box.extend(p);
    slot->box.min().array() -= margin;
    slot->box.max().array() += margin;
    slot->field = std::make_unique<ConvexPolytopeField>(std::move(vertices), std::move(triangles), margin);
  }
  return *slot;
}

const ConvexPolytopeField* ConvexShapeCache::field(const btConvexShape* shape) {
  return entry(shape).field.get();
}

double ConvexShapeCache::thinnestExtent(const btConvexShape* shape) {
  const Entry& e = entry(shape);
  return e.field ? e.box.sizes().minCoeff() : 0.0;
}

const PointTree* ConvexShapeCache::shell(const btConvexShape* shape, double spacing, int maxPoints) {
  Entry& e = entry(shape);
  if (!e.field) return nullptr;
  std::unique_ptr<PointTree>& tree = e.shells[{spacing, maxPoints}];
  if (!tree) {
    // At most maxPoints: the spacing grows with the square root of the excess.
    const auto& v = e.field->vertices();
    PointShell points = sampleGrownSurface(v, e.faces, e.field->radius(), spacing);
    for (double grown = spacing; points.size() > static_cast<std::size_t>(maxPoints);) {
      grown *= 1.05 * std::sqrt(double(points.size()) / maxPoints);
      points = sampleGrownSurface(v, e.faces, e.field->radius(), grown);
    }
    tree = std::make_unique<PointTree>(std::move(points));
  }
  return tree.get();
}

std::optional<RevolvedConvexField> revolvedField(const btCollisionShape* shape) {
  const double margin = double(shape->getMargin());
  if (shape->getShapeType() == CYLINDER_SHAPE_PROXYTYPE) {
    const auto* cylinder = static_cast<const btCylinderShape*>(shape);
    const int axis = cylinder->getUpAxis();
    const Vec3 half = toVec3(cylinder->getHalfExtentsWithoutMargin());
    return cylinderField(half[(axis + 1) % 3], half[axis], axis, margin);
  }
  if (shape->getShapeType() == CONE_SHAPE_PROXYTYPE) {
    const auto* cone = static_cast<const btConeShape*>(shape);
    return coneField(double(cone->getRadius()), double(cone->getHeight()), cone->getConeUpIndex(), margin);
  }
  return std::nullopt;
}

void meshTriangles(const btCollisionShape* shape, const Box3& boxInShape, std::vector<Vec3>& outVertices,
                   std::vector<TriangleIndices>& outTriangles) {
  TriangleCollector collector;
  static_cast<const btConcaveShape*>(shape)->processAllTriangles(&collector, toBt(boxInShape.min()),
                                                                 toBt(boxInShape.max()));
  outVertices = std::move(collector.vertices);
  outTriangles = std::move(collector.triangles);
}

std::optional<TriangleSetField> meshTrianglesInBox(const btCollisionShape* shape, const Box3& boxInShape,
                                                   double thickness, const Vec3& outside) {
  TriangleCollector collector;
  meshTriangles(shape, boxInShape, collector.vertices, collector.triangles);
  if (collector.triangles.empty()) return std::nullopt;
  try {
    return TriangleSetField(std::move(collector.vertices), std::move(collector.triangles), double(shape->getMargin()),
                            thickness, outside);
  } catch (const Error&) {
    return std::nullopt;  // every triangle in the box has zero area
  }
}

}  // namespace sdfccd::bullet::detail
