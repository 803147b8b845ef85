/// @file
/// @brief RunFrameRenderer: a run's bodies and poses into RenderScenes, PNG files named by frame.
#include "cli/run_frame_renderer.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "sdfccd/error.h"

#if SDFCCD_HAS_RENDER
#include "sdfccd/render/offscreen_renderer.h"
#include "sdfccd/render/png_file.h"
#endif

namespace sdfccd::cli {

void parseImageSize(const std::string& text, int& outWidth, int& outHeight) {
  int width = 0;
  int height = 0;
  char x = 0;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &extra) != 3 || (x != 'x' && x != 'X') || width < 1 ||
      height < 1 || width > 8192 || height > 8192) {
    throw Error("image size must be WIDTHxHEIGHT between 1x1 and 8192x8192, got '" + text + "'");
  }
  outWidth = width;
  outHeight = height;
}

FrameRenderSettings frameRenderSettingsFor(const RunScene& scene) {
  FrameRenderSettings settings;
  settings.groundHeight = scene.groundHeight;
  settings.camera = scene.camera;
  return settings;
}

std::string RunFrameRenderer::framePath(const std::string& outputDir, int frameNumber) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%05d.png", frameNumber);
  return (std::filesystem::path(outputDir) / name).string();
}

bool RunFrameRenderer::wantsFrame(int frameNumber) const {
  return frameNumber >= 0 && frameNumber % std::max(1, m_settingsEvery) == 0;
}

std::unique_ptr<RunFrameRenderer> makeSceneFrameRenderer(const std::string& scenePath, const std::string& size,
                                                         int every, const std::string& outputDir) {
#if !SDFCCD_HAS_RENDER
  throw Error("this sdfccd was built without the renderer (-DSDFCCD_BUILD_RENDER=OFF)");
#endif
  RunScene scene = readRunScene(scenePath);
  FrameRenderSettings settings = frameRenderSettingsFor(scene);
  parseImageSize(size, settings.width, settings.height);
  if (every < 1) throw Error("--every must be at least 1 (got " + std::to_string(every) + ")");
  settings.every = every;
  std::error_code error;
  std::filesystem::create_directories(outputDir, error);
  if (error || !std::filesystem::is_directory(outputDir)) {
    throw Error("cannot create the frames folder '" + outputDir + "'" + (error ? ": " + error.message() : ""));
  }
  loadRunMeshes(scene);
  return std::make_unique<RunFrameRenderer>(scene.bodies, settings);
}

#if SDFCCD_HAS_RENDER

namespace {

// Distinguishable, colour-blind-friendly body colours (Okabe-Ito), repeated; static bodies are grey.
const render::Color kPalette[] = {
    {0.90f, 0.62f, 0.00f}, {0.34f, 0.71f, 0.91f}, {0.00f, 0.62f, 0.45f}, {0.94f, 0.89f, 0.26f},
    {0.00f, 0.45f, 0.70f}, {0.84f, 0.37f, 0.00f}, {0.80f, 0.47f, 0.65f},
};

}  // namespace

struct RunFrameRenderer::Impl {
  std::vector<RunBody> bodies;
  FrameRenderSettings settings;
  render::OffscreenRenderer renderer;
  std::optional<render::RenderCamera> camera;  // fixed at the first frame

  render::RenderScene scene(const std::vector<Rigid>& worldFromBody, const std::vector<FramePoints>& points) const {
    if (worldFromBody.size() != bodies.size()) {
      throw Error("render: " + std::to_string(worldFromBody.size()) + " poses for " + std::to_string(bodies.size()) +
                  " bodies");
    }
    render::RenderScene result;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      render::RenderMesh mesh;
      mesh.name = bodies[i].name;
      mesh.mesh = bodies[i].mesh;
      mesh.scale = 1.0;  // RunBody meshes are scaled already
      mesh.worldFromBody = worldFromBody[i];
      mesh.color = bodies[i].isStatic ? render::Color(0.62f, 0.64f, 0.70f)
                                      : kPalette[i % (sizeof(kPalette) / sizeof(kPalette[0]))];
      result.meshes.push_back(std::move(mesh));
    }
    if (settings.groundHeight) {
      render::RenderGround ground;
      ground.height = *settings.groundHeight;
      result.ground = ground;
    }
    for (const FramePoints& set : points) {
      render::RenderPointSet pointSet;
      pointSet.pointsInWorld = set.pointsInWorld;
      pointSet.depths = set.depths;
      pointSet.maxDepth = set.maxDepth;
      pointSet.pointSize = 2.0f;
      result.pointSets.push_back(std::move(pointSet));
    }
    return result;
  }

  render::RenderSettings renderSettings(int width, int height) const {
    render::RenderSettings s;
    s.width = width > 0 ? width : settings.width;
    s.height = height > 0 ? height : settings.height;
    s.supersample = settings.supersample;
    return s;
  }

  void fixCamera(render::RenderScene& ioScene) {
    if (!camera) {
      if (settings.camera) {
        render::RenderCamera c;
        c.eye = settings.camera->eye;
        c.target = settings.camera->target;
        c.up = settings.camera->up;
        c.fovDegrees = settings.camera->fovDegrees;
        c.validate();
        camera = c;
      } else {
        if (settings.framingPoints.empty()) {
          camera = render::OffscreenRenderer::cameraFor(ioScene, renderSettings(0, 0));
        } else {
          std::vector<Vec3> points = settings.framingPoints;
          if (settings.groundHeight) {
            for (const Vec3& p : settings.framingPoints) points.emplace_back(p.x(), *settings.groundHeight, p.z());
          }
          camera = render::framePoints(points, static_cast<double>(settings.width) / settings.height);
        }
      }
    }
    ioScene.camera = camera;
  }

  render::RgbImage draw(const std::vector<Rigid>& worldFromBody, const std::vector<FramePoints>& points, int width,
                        int height) {
    render::RenderScene frame = scene(worldFromBody, points);
    fixCamera(frame);
    return renderer.render(frame, renderSettings(width, height));
  }
};

RunFrameRenderer::RunFrameRenderer(std::vector<RunBody> bodies, FrameRenderSettings settings)
    : m_impl(std::make_unique<Impl>()) {
  if (settings.every < 1) throw Error("render: --every must be at least 1");
  if (settings.width < 1 || settings.height < 1 || settings.width > 8192 || settings.height > 8192) {
    throw Error("render: bad image size");
  }
  for (const RunBody& body : bodies) {
    if (!body.mesh) throw Error("render: body '" + body.name + "' has no mesh loaded");
  }
  m_impl->bodies = std::move(bodies);
  m_impl->settings = std::move(settings);
  m_settingsEvery = m_impl->settings.every;
}

RunFrameRenderer::~RunFrameRenderer() = default;

bool RunFrameRenderer::renderRunFrame(int frameNumber, const std::vector<Rigid>& worldFromBody,
                                      const std::string& outputDir, const std::vector<FramePoints>& points) {
  if (!wantsFrame(frameNumber)) return false;
  renderToFile(worldFromBody, framePath(outputDir, frameNumber), points);
  return true;
}

void RunFrameRenderer::renderToFile(const std::vector<Rigid>& worldFromBody, const std::string& path,
                                    const std::vector<FramePoints>& points) {
  render::writePng(path, m_impl->draw(worldFromBody, points, 0, 0));
}

render::RgbImage RunFrameRenderer::renderImage(const std::vector<Rigid>& worldFromBody,
                                               const std::vector<FramePoints>& points, int width, int height) {
  return m_impl->draw(worldFromBody, points, width, height);
}

#else  // built without the renderer

struct RunFrameRenderer::Impl {};

RunFrameRenderer::RunFrameRenderer(std::vector<RunBody>, FrameRenderSettings) {
  throw Error("this sdfccd was built without the renderer (-DSDFCCD_BUILD_RENDER=OFF)");
}

RunFrameRenderer::~RunFrameRenderer() = default;

bool RunFrameRenderer::renderRunFrame(int, const std::vector<Rigid>&, const std::string&,
                                      const std::vector<FramePoints>&) {
  return false;
}

void RunFrameRenderer::renderToFile(const std::vector<Rigid>&, const std::string&, const std::vector<FramePoints>&) {}

#endif

}  // namespace sdfccd::cli
