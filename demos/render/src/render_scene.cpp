/// @file
/// @brief RenderScene helpers: world bounds of bodies (with input checks) and the depth colour ramp.
#include "sdfccd/render/render_scene.h"

#include <algorithm>
#include <cmath>

#include "sdfccd/error.h"

namespace sdfccd::render {

Color depthColor(double depth, double maxDepth, const Color& base) {
  if (!(depth > 0.0)) return base;
  const float t = maxDepth > 0.0 ? static_cast<float>(std::min(1.0, depth / maxDepth)) : 1.0f;
  const Color shallow(1.0f, 0.92f, 0.10f);
  const Color deep(0.86f, 0.0f, 0.0f);
  return (1.0f - t) * shallow + t * deep;
}

Box3 worldBounds(const RenderMesh& body) {
  const std::string name = body.name.empty() ? std::string("(unnamed)") : body.name;
  if (!body.mesh) throw Error("render: body '" + name + "' has no mesh");
  if (body.mesh->vertices.empty() || body.mesh->triangles.empty()) {
    throw Error("render: body '" + name + "' has an empty mesh");
  }
  if (!(body.scale > 0.0) || !std::isfinite(body.scale)) {
    throw Error("render: body '" + name + "' has a non-positive or non-finite scale");
  }
  if (!body.worldFromBody.matrix().allFinite()) throw Error("render: body '" + name + "' has a non-finite pose");
  Box3 box;
  for (const Vec3& vertex : body.mesh->vertices) box.extend(body.worldFromBody * (body.scale * vertex));
  if (!box.min().allFinite() || !box.max().allFinite()) {
    throw Error("render: body '" + name + "' has non-finite vertices");
  }
  return box;
}

Box3 worldBounds(const RenderScene& scene) {
  Box3 box;
  for (const RenderMesh& body : scene.meshes) box.extend(worldBounds(body));
  return box;
}

}  // namespace sdfccd::render
