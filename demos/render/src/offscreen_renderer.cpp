/// @file
/// @brief OffscreenRenderer: OSMesa context, fixed-function GL drawing of bodies, ground, grid and points.
#include "sdfccd/render/offscreen_renderer.h"

#include <GL/gl.h>
#include <GL/osmesa.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>

#include "sdfccd/error.h"

namespace sdfccd::render {

namespace offscreen_detail {
/// A mesh converted to float arrays for glDrawArrays/glDrawElements, in body coordinates (named, not file-local:
/// OffscreenRenderer::Impl holds them).
struct GpuMesh {
  std::weak_ptr<const TriangleMesh> owner;  // detects a freed mesh whose address is reused
  Shading shading = Shading::Smooth;
  std::vector<float> positions;   // 3 per vertex
  std::vector<float> normals;     // 3 per vertex
  std::vector<unsigned> indices;  // smooth shading only
};
}  // namespace offscreen_detail
using offscreen_detail::GpuMesh;

namespace {

constexpr int kMaxRenderSide = 8192;  // pixels, after supersampling (llvmpipe allows 16384; memory stays sane)

GpuMesh convertMesh(const std::shared_ptr<const TriangleMesh>& mesh, Shading shading) {
  GpuMesh gpu;
  gpu.owner = mesh;
  gpu.shading = shading;
  const std::vector<Vec3>& vertices = mesh->vertices;
  const int vertexCount = static_cast<int>(vertices.size());
  for (const auto& triangle : mesh->triangles) {
    for (int index : triangle) {
      if (index < 0 || index >= vertexCount) throw Error("render: a mesh has a triangle index out of range");
    }
  }
  auto faceNormal = [&](const std::array<int, 3>& t) -> Vec3 {  // length = twice the area
    return (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
  };
  auto push = [](std::vector<float>& out, const Vec3& v) {
    out.push_back(static_cast<float>(v.x()));
    out.push_back(static_cast<float>(v.y()));
    out.push_back(static_cast<float>(v.z()));
  };
  if (shading == Shading::Flat) {
    gpu.positions.reserve(mesh->triangles.size() * 9);
    gpu.normals.reserve(mesh->triangles.size() * 9);
    for (const auto& t : mesh->triangles) {
      const Vec3 n = faceNormal(t);
      const Vec3 unit = n.norm() > 0.0 ? Vec3(n.normalized()) : Vec3(0.0, 1.0, 0.0);
      for (int index : t) {
        push(gpu.positions, vertices[index]);
        push(gpu.normals, unit);
      }
    }
  } else {
    // Area-weighted vertex normals: the unnormalised face normal carries the area weight.
    std::vector<Vec3> sums(vertices.size(), Vec3::Zero());
    for (const auto& t : mesh->triangles) {
      const Vec3 n = faceNormal(t);
      for (int index : t) sums[index] += n;
    }
    gpu.positions.reserve(vertices.size() * 3);
    gpu.normals.reserve(vertices.size() * 3);
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      push(gpu.positions, vertices[i]);
      push(gpu.normals, sums[i].norm() > 0.0 ? Vec3(sums[i].normalized()) : Vec3(0.0, 1.0, 0.0));
    }
    gpu.indices.reserve(mesh->triangles.size() * 3);
    for (const auto& t : mesh->triangles) {
      for (int index : t) gpu.indices.push_back(static_cast<unsigned>(index));
    }
  }
  return gpu;
}

/// A "nice" grid step (1, 2 or 5 times a power of ten) close to `approximate`.
double niceStep(double approximate) {
  const double decade = std::pow(10.0, std::floor(std::log10(approximate)));
  const double mantissa = approximate / decade;
  const double nice = mantissa < 1.5 ? 1.0 : mantissa < 3.5 ? 2.0 : mantissa < 7.5 ? 5.0 : 10.0;
  return nice * decade;
}

void validateSettings(const RenderSettings& settings) {
  if (settings.width < 1 || settings.height < 1 || settings.width > kMaxRenderSide ||
      settings.height > kMaxRenderSide) {
    throw Error("render: image size must be between 1x1 and " + std::to_string(kMaxRenderSide) + "x" +
                std::to_string(kMaxRenderSide) + ", got " + std::to_string(settings.width) + "x" +
                std::to_string(settings.height));
  }
  if (settings.supersample < 1 || settings.supersample > 8 ||
      static_cast<long>(settings.width) * settings.supersample > kMaxRenderSide ||
      static_cast<long>(settings.height) * settings.supersample > kMaxRenderSide) {
    throw Error("render: supersampling factor " + std::to_string(settings.supersample) +
                " is out of range for this image size");
  }
  if (!settings.background.allFinite()) throw Error("render: the background colour is not finite");
}

void validatePoints(const RenderPointSet& set) {
  if (!set.depths.empty() && set.depths.size() != set.pointsInWorld.size()) {
    throw Error("render: a point set has " + std::to_string(set.depths.size()) + " depths for " +
                std::to_string(set.pointsInWorld.size()) + " points");
  }
  for (const Vec3& p : set.pointsInWorld) {
    if (!p.allFinite()) throw Error("render: a point set has a non-finite point");
  }
  for (double d : set.depths) {
    if (!std::isfinite(d)) throw Error("render: a point set has a non-finite depth");
  }
  if (!(set.pointSize > 0.0f) || !(set.contactPointSize > 0.0f) || !std::isfinite(set.maxDepth)) {
    throw Error("render: a point set has a bad point size or maxDepth");
  }
}

/// Bodies and points together: what the camera frames and the clip range must hold.
Box3 contentBounds(const RenderScene& scene) {
  Box3 box = worldBounds(scene);
  for (const RenderPointSet& set : scene.pointSets) {
    validatePoints(set);
    for (const Vec3& p : set.pointsInWorld) box.extend(p);
  }
  return box;
}

void glColor(const Color& c) {
  glColor3f(c.x(), c.y(), c.z());
}

}  // namespace

struct OffscreenRenderer::Impl {
  OSMesaContext context = nullptr;
  std::vector<std::uint8_t> buffer;  // RGBA, bottom row first (OSMesa's default)
  std::map<const TriangleMesh*, GpuMesh> meshes;

  const GpuMesh& gpuMesh(const std::shared_ptr<const TriangleMesh>& mesh, Shading shading) {
    auto it = meshes.find(mesh.get());
    if (it != meshes.end() && it->second.shading == shading && it->second.owner.lock() == mesh) return it->second;
    // Forget meshes that no longer exist, so the cache does not grow over a long run.
    for (auto stale = meshes.begin(); stale != meshes.end();) {
      stale = stale->second.owner.expired() ? meshes.erase(stale) : std::next(stale);
    }
    return meshes[mesh.get()] = convertMesh(mesh, shading);
  }
};

OffscreenRenderer::OffscreenRenderer() : m_impl(std::make_unique<Impl>()) {
  m_impl->context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (m_impl->context == nullptr) throw Error("render: cannot create an OSMesa context");
}

OffscreenRenderer::~OffscreenRenderer() {
  if (m_impl->context != nullptr) OSMesaDestroyContext(m_impl->context);
}

RenderCamera OffscreenRenderer::cameraFor(const RenderScene& scene, const RenderSettings& settings) {
  if (scene.camera) {
    scene.camera->validate();
    return *scene.camera;
  }
  // The corners of every body's box and every point, and their shadows on the ground: bodies fall, and
  // where they land stays in view.
  contentBounds(scene);  // validates
  std::vector<Vec3> points;
  for (const RenderMesh& body : scene.meshes) {
    const Box3 box = worldBounds(body);
    for (int corner = 0; corner < 8; ++corner) points.push_back(box.corner(static_cast<Box3::CornerType>(corner)));
  }
  for (const RenderPointSet& set : scene.pointSets)
    points.insert(points.end(), set.pointsInWorld.begin(), set.pointsInWorld.end());
  if (scene.ground) {
    const std::size_t count = points.size();
    for (std::size_t i = 0; i < count; ++i) points.emplace_back(points[i].x(), scene.ground->height, points[i].z());
  }
  return framePoints(points, static_cast<double>(settings.width) / settings.height, settings.framing);
}

RgbImage OffscreenRenderer::render(const RenderScene& scene, const RenderSettings& settings) {
  validateSettings(settings);
  const Box3 content = contentBounds(scene);  // also validates every body and point set
  if (scene.ground && !std::isfinite(scene.ground->height)) throw Error("render: the ground height is not finite");
  if (scene.ground && !(scene.ground->gridSpacing >= 0.0 && std::isfinite(scene.ground->gridSpacing))) {
    throw Error("render: the ground grid spacing must be >= 0");
  }
  const RenderCamera camera = cameraFor(scene, settings);

  const int ss = settings.supersample;
  const int width = settings.width * ss;
  const int height = settings.height * ss;
  m_impl->buffer.assign(static_cast<std::size_t>(width) * height * 4, 0);
  if (!OSMesaMakeCurrent(m_impl->context, m_impl->buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
    throw Error("render: OSMesa cannot render a " + std::to_string(width) + "x" + std::to_string(height) + " image");
  }

  // Sizes of what is drawn come from the camera, not from the bodies, so that under a fixed camera the ground,
  // its grid and the clip range stay put from frame to frame while bodies move. `viewScale` is the half-height
  // of the view at the target; the ground square reaches far beyond it (its edge then sits on the horizon).
  const double eyeToTarget = (camera.eye - camera.target).norm();
  const double viewScale =
      std::max(eyeToTarget * std::tan(0.5 * camera.fovDegrees * 3.14159265358979323846 / 180.0), 1e-3);
  const double groundHalf = 400.0 * viewScale;
  const Vec3 groundCentre(camera.target.x(), 0.0, camera.target.z());
  double farDistance = eyeToTarget + 1.5 * groundHalf;
  double nearDistance = 0.5 * eyeToTarget;
  if (!content.isEmpty()) {
    // Bodies and points, wherever they are, lie inside the clip range.
    const double contentRadius = 0.5 * content.diagonal().norm();
    const double eyeToContent = (camera.eye - content.center()).norm();
    farDistance = std::max(farDistance, eyeToContent + 2.0 * contentRadius);
    nearDistance = std::min(nearDistance, 0.5 * (eyeToContent - contentRadius));
  }
  if (scene.ground) nearDistance = std::min(nearDistance, 0.5 * std::abs(camera.eye.y() - scene.ground->height));
  nearDistance = std::max(nearDistance, 1e-5 * farDistance);

  glViewport(0, 0, width, height);
  glClearColor(settings.background.x(), settings.background.y(), settings.background.z(), 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DITHER);  // dithering would make colours depend on pixel position, not only on the scene
  glShadeModel(settings.shading == Shading::Flat ? GL_FLAT : GL_SMOOTH);

  glMatrixMode(GL_PROJECTION);
  const Eigen::Matrix4d projection = camera.projection(static_cast<double>(width) / height, nearDistance, farDistance);
  glLoadMatrixd(projection.data());  // Eigen is column-major, as GL expects
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();

  // One directional light fixed to the camera (set while the modelview is the identity), from above-left-behind.
  const GLfloat lightDirection[4] = {-0.35f, 0.75f, 0.55f, 0.0f};
  const GLfloat ambient[4] = {0.30f, 0.30f, 0.30f, 1.0f};
  const GLfloat diffuse[4] = {0.75f, 0.75f, 0.75f, 1.0f};
  const GLfloat specular[4] = {0.15f, 0.15f, 0.15f, 1.0f};
  const GLfloat noAmbient[4] = {0.0f, 0.0f, 0.0f, 1.0f};
  glLightfv(GL_LIGHT0, GL_POSITION, lightDirection);
  glLightfv(GL_LIGHT0, GL_AMBIENT, ambient);
  glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
  glLightfv(GL_LIGHT0, GL_SPECULAR, specular);
  glLightModelfv(GL_LIGHT_MODEL_AMBIENT, noAmbient);
  glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
  glEnable(GL_LIGHT0);
  glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
  glEnable(GL_COLOR_MATERIAL);
  const GLfloat materialSpecular[4] = {1.0f, 1.0f, 1.0f, 1.0f};
  glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, materialSpecular);
  glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, 24.0f);
  glEnable(GL_NORMALIZE);  // the uniform body scale is in the modelview

  const Rigid viewFromWorld = camera.viewFromWorld();
  glLoadMatrixd(viewFromWorld.matrix().data());

  // Surfaces are pushed back a little so grid lines and surface points drawn on them win the depth test.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 1.0f);

  if (scene.ground) {
    const RenderGround& ground = *scene.ground;
    const double y = ground.height;
    const double cx = groundCentre.x();
    const double cz = groundCentre.z();
    glEnable(GL_LIGHTING);
    glColor(ground.color);
    glBegin(GL_QUADS);
    glNormal3d(0.0, 1.0, 0.0);
    glVertex3d(cx - groundHalf, y, cz - groundHalf);
    glVertex3d(cx - groundHalf, y, cz + groundHalf);
    glVertex3d(cx + groundHalf, y, cz + groundHalf);
    glVertex3d(cx + groundHalf, y, cz - groundHalf);
    glEnd();

    // Grid lines on multiples of the step (world-fixed), over a square a few view sizes wide: further out
    // they would only alias into a grey blur.
    glDisable(GL_LIGHTING);
    const double step = ground.gridSpacing > 0.0 ? ground.gridSpacing : niceStep(viewScale / 2.5);
    const double gridHalf = std::min(groundHalf, 6.0 * viewScale);
    const long first = static_cast<long>(std::floor((-gridHalf) / step));
    const long last = static_cast<long>(std::ceil(gridHalf / step));
    if (last - first <= 4000) {
      glLineWidth(static_cast<float>(ss));
      glColor(ground.lineColor);
      glBegin(GL_LINES);
      const double baseX = std::round(cx / step) * step;
      const double baseZ = std::round(cz / step) * step;
      for (long i = first; i <= last; ++i) {
        const double x = baseX + static_cast<double>(i) * step;
        const double z = baseZ + static_cast<double>(i) * step;
        glVertex3d(x, y, baseZ - gridHalf);
        glVertex3d(x, y, baseZ + gridHalf);
        glVertex3d(baseX - gridHalf, y, z);
        glVertex3d(baseX + gridHalf, y, z);
      }
      glEnd();
    }
  }

  glEnable(GL_LIGHTING);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_NORMAL_ARRAY);
  for (const RenderMesh& body : scene.meshes) {
    if (!body.color.allFinite()) throw Error("render: body '" + body.name + "' has a non-finite colour");
    const GpuMesh& gpu = m_impl->gpuMesh(body.mesh, settings.shading);
    const Eigen::Affine3d worldFromModel = body.worldFromBody * Eigen::Scaling(body.scale);
    glPushMatrix();
    glMultMatrixd(worldFromModel.matrix().data());
    glColor(body.color);
    glVertexPointer(3, GL_FLOAT, 0, gpu.positions.data());
    glNormalPointer(GL_FLOAT, 0, gpu.normals.data());
    if (settings.shading == Shading::Flat) {
      glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(gpu.positions.size() / 3));
    } else {
      glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(gpu.indices.size()), GL_UNSIGNED_INT, gpu.indices.data());
    }
    glPopMatrix();
  }
  glDisableClientState(GL_NORMAL_ARRAY);
  glDisableClientState(GL_VERTEX_ARRAY);

  // Points: plain ones depth tested, then contacts from shallow to deep so the deepest ends on top.
  glDisable(GL_LIGHTING);
  for (const RenderPointSet& set : scene.pointSets) {
    double maxDepth = set.maxDepth;
    if (maxDepth <= 0.0 && !set.depths.empty()) maxDepth = *std::max_element(set.depths.begin(), set.depths.end());
    std::vector<std::size_t> contacts;
    glPointSize(set.pointSize * static_cast<float>(ss));
    glBegin(GL_POINTS);
    glColor(set.color);
    for (std::size_t i = 0; i < set.pointsInWorld.size(); ++i) {
      if (!set.depths.empty() && set.depths[i] > 0.0) {
        contacts.push_back(i);
        continue;
      }
      const Vec3& p = set.pointsInWorld[i];
      glVertex3d(p.x(), p.y(), p.z());
    }
    glEnd();
    if (contacts.empty()) continue;
    std::stable_sort(contacts.begin(), contacts.end(),
                     [&](std::size_t a, std::size_t b) { return set.depths[a] < set.depths[b]; });
    if (set.contactsOnTop) glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);  // the coloured point lies at its rim's depth
    // Each contact gets a dark rim (a bigger point underneath) so it reads on a body of any colour.
    for (std::size_t i : contacts) {
      const Vec3& p = set.pointsInWorld[i];
      glPointSize((set.contactPointSize + 2.0f) * static_cast<float>(ss));
      glBegin(GL_POINTS);
      glColor3f(0.05f, 0.05f, 0.05f);
      glVertex3d(p.x(), p.y(), p.z());
      glEnd();
      glPointSize(set.contactPointSize * static_cast<float>(ss));
      glBegin(GL_POINTS);
      glColor(depthColor(set.depths[i], maxDepth, set.color));
      glVertex3d(p.x(), p.y(), p.z());
      glEnd();
    }
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
  }

  glFinish();
  const GLenum glError = glGetError();
  if (glError != GL_NO_ERROR) throw Error("render: OpenGL error " + std::to_string(glError));

  // OSMesa's buffer starts at the bottom row; images start at the top.
  RgbImage full(width, height);
  for (int row = 0; row < height; ++row) {
    const std::uint8_t* source = m_impl->buffer.data() + static_cast<std::size_t>(height - 1 - row) * width * 4;
    std::uint8_t* target = full.at(0, row);
    for (int x = 0; x < width; ++x) {
      target[3 * x] = source[4 * x];
      target[3 * x + 1] = source[4 * x + 1];
      target[3 * x + 2] = source[4 * x + 2];
    }
  }
  return downsample(full, ss);
}

}  // namespace sdfccd::render
