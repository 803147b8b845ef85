/// @file
/// @brief RunFrameRenderer: PNG frames of a run (bodies at their poses, ground, contacts) for simulate and render.
///
/// @details The glue between runs and sdfccd_render. Build one per run from the run's bodies (meshes already
/// loaded and shared), then hand it each frame's poses: `renderRunFrame(frame, poses, dir)` writes
/// `dir/frame_00042.png` when the frame number is a multiple of `every`. The camera is fixed for the whole run:
/// the scene's "camera" if it has one, else `framingPoints` if given, else automatic framing of the first frame
/// rendered (the bodies' box extended down to the ground, so where they fall stays in view).
/// Built without the renderer (-DSDFCCD_BUILD_RENDER=OFF), the constructor throws a clear sdfccd::Error.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/run_folder.h"
#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"

#if SDFCCD_HAS_RENDER
#include "sdfccd/render/rgb_image.h"
#endif

namespace sdfccd::cli {

/// Image size and choices of a run's frames.
struct FrameRenderSettings {
  int width = 960;                     ///< pixels
  int height = 540;                    ///< pixels
  int every = 1;                       ///< render frames whose number is a multiple of this (>= 1)
  int supersample = 2;                 ///< anti-aliasing factor (1 = none)
  std::optional<double> groundHeight;  ///< y of the ground (m); no ground drawn when empty
  std::optional<SceneCamera> camera;   ///< the scene's camera; empty = automatic framing
  std::vector<Vec3> framingPoints;     ///< world points to frame automatically (m), e.g. a whole run's body
                                       ///< box corners; empty = the first frame's
};

/// Points to draw over a frame (e.g. a body's point shell): depth > 0 marks a contact (m).
struct FramePoints {
  std::vector<Vec3> pointsInWorld;  ///< (m)
  std::vector<double> depths;       ///< empty, or one penetration depth per point (m)
  double maxDepth = 0.0;            ///< depth drawn fully red (m); 0 = the largest depth in the set
};

/// Parses "WIDTHxHEIGHT" (e.g. "1280x720"). Throws sdfccd::Error for anything else or sizes outside 1..8192.
void parseImageSize(const std::string& text, int& outWidth, int& outHeight);

/// The settings for a scene: its ground and camera.
FrameRenderSettings frameRenderSettingsFor(const RunScene& scene);

/// A body pose from a position (centre of mass, m) and an orientation, as the simulation reports them.
inline Rigid bodyPose(const Vec3& position, const Quat& orientation) {
  Rigid worldFromBody = Rigid::Identity();
  worldFromBody.linear() = orientation.normalized().toRotationMatrix();
  worldFromBody.translation() = position;
  return worldFromBody;
}

/// Renders the frames of one run. Not thread-safe (one per thread).
class RunFrameRenderer {
 public:
  /// `bodies` in the order in which poses will be given; their meshes must be loaded, scaled and in the body
  /// frame the poses are of (loadRunMeshes does that; a simulation can pass its models' meshes in body frame).
  /// Throws sdfccd::Error for a body without a mesh, bad settings, or a build without the renderer.
  RunFrameRenderer(std::vector<RunBody> bodies, FrameRenderSettings settings);
  ~RunFrameRenderer();
  RunFrameRenderer(const RunFrameRenderer&) = delete;
  RunFrameRenderer& operator=(const RunFrameRenderer&) = delete;

  /// True when `frameNumber` is one that renderRunFrame writes (a multiple of `every`).
  bool wantsFrame(int frameNumber) const;
  /// The file a frame goes to: outputDir/frame_%05d.png.
  static std::string framePath(const std::string& outputDir, int frameNumber);
  /// Writes outputDir/frame_%05d.png if wantsFrame(frameNumber); returns whether it did. The folder must
  /// exist. Throws sdfccd::Error for a wrong pose count, non-finite poses or an unwritable folder.
  bool renderRunFrame(int frameNumber, const std::vector<Rigid>& worldFromBody, const std::string& outputDir,
                      const std::vector<FramePoints>& points = {});
  /// Renders one frame to `path` whatever its number.
  void renderToFile(const std::vector<Rigid>& worldFromBody, const std::string& path,
                    const std::vector<FramePoints>& points = {});

#if SDFCCD_HAS_RENDER
  /// Renders one frame in memory at `width` x `height` (0 = the settings' size), same camera as the files.
  render::RgbImage renderImage(const std::vector<Rigid>& worldFromBody, const std::vector<FramePoints>& points = {},
                               int width = 0, int height = 0);
#endif

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
  int m_settingsEvery = 1;
};

/// For `sdfccd simulate SCENE --render DIR [--every K] [--size WxH]`: reads SCENE's bodies, ground and camera
/// (readRunScene), loads their meshes into the body frame (loadRunMeshes), creates DIR, and returns a renderer
/// for poses given in scene body order. Throws sdfccd::Error for a bad size, every < 1, a folder that cannot be
/// created, a mesh that cannot be loaded, or a build without the renderer.
std::unique_ptr<RunFrameRenderer> makeSceneFrameRenderer(const std::string& scenePath, const std::string& size,
                                                         int every, const std::string& outputDir);

}  // namespace sdfccd::cli
