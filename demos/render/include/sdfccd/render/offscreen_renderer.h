/// @file
/// @brief OffscreenRenderer: draws a RenderScene into an RgbImage with OSMesa, without a display or GPU.
///
/// @details Mesa's OSMesa renders into a buffer in memory (gallium llvmpipe on Debian 12, which offers GL 4.5
/// compatibility; we use only the GL 1.x fixed-function pipeline so any OSMesa works). Meshes are depth tested
/// and lit by one directional light fixed to the camera (from above, left and behind the viewer) plus ambient,
/// two-sided so open meshes (the bowl) read correctly; flat (face normals) or smooth (area-weighted vertex
/// normals) shading. The ground is a lit square under the bodies with grid lines drawn over it (polygon offset
/// keeps the lines from z-fighting). Anti-aliasing is supersampling: render `supersample` times larger and
/// average blocks (deterministic, unlike driver MSAA choices).
///
/// Determinism: the same scene and settings give the same image on the same machine (llvmpipe's rasterisation
/// does not depend on its thread count). Thread safety: one OffscreenRenderer per thread; an instance makes its
/// own OSMesa context current on the calling thread for each render() and is not safe to share.
#pragma once

#include <memory>

#include "sdfccd/render/render_scene.h"
#include "sdfccd/render/rgb_image.h"

namespace sdfccd::render {

/// Shading of meshes.
enum class Shading { Flat, Smooth };

/// Image size and look of one render.
struct RenderSettings {
  int width = 960;      ///< output pixels (1..8192)
  int height = 540;     ///< output pixels (1..8192)
  int supersample = 2;  ///< anti-aliasing factor (1 = none; width*factor <= 8192)
  Shading shading = Shading::Smooth;
  Color background = Color(0.92f, 0.94f, 0.97f);  ///< sky colour
  CameraFramingSettings framing;                  ///< used when the scene has no camera
};

/// Renders scenes offscreen. Creating it creates an OSMesa context (throws sdfccd::Error if OSMesa fails).
class OffscreenRenderer {
 public:
  OffscreenRenderer();
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  /// Draws `scene`. Throws sdfccd::Error for bad settings, a body without a mesh or with an empty mesh,
  /// non-finite poses or points, mismatched depth arrays or a bad camera.
  RgbImage render(const RenderScene& scene, const RenderSettings& settings);

  /// The camera render() uses for `scene` (the scene's own, or automatic framing of its bodies).
  static RenderCamera cameraFor(const RenderScene& scene, const RenderSettings& settings);

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace sdfccd::render
