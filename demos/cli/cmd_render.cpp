/// @file
/// @brief `sdfccd render RUN_DIR [--size WxH] [--every K]`: frames, a contact sheet and an MP4 of a saved run.
///
/// @details Re-renders a run from its per-frame CSV (no re-simulation): RUN_DIR/frames/frame_%05d.png (named by
/// frame number), RUN_DIR/contact_sheet.png (evenly spaced frames, first and last included, left to right then
/// top to bottom) and, when ffmpeg is on PATH, RUN_DIR/frames.mp4 (skipped with a note otherwise). The camera is
/// the scene's "camera", else one automatic framing of every pose of the run, fixed for all frames.
/// A haptic run folder (`sdfccd haptics --out`, haptic_run.h) is drawn the same way: the tool at the poses of
/// ticks.csv (frame numbers are ticks) and the obstacle, from the scene summary.json names.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/command_registry.h"
#if SDFCCD_HAS_HAPTICS
#include "cli/haptic_run.h"
#include "sdfccd/model/model_cache_folder.h"
#endif
#include "cli/external_program.h"
#include "cli/progress_bar.h"
#include "cli/run_folder.h"
#include "cli/run_frame_renderer.h"
#include "cli/scratch_folder.h"
#include "sdfccd/error.h"
#include "sdfccd/output_file.h"

#if SDFCCD_HAS_RENDER
#include "sdfccd/render/contact_sheet.h"
#include "sdfccd/render/png_file.h"
#include "sdfccd/render/render_camera.h"
#endif

namespace sdfccd::cli {
namespace {

namespace fs = std::filesystem;

struct RenderOptions {
  std::string runDir;
  std::string size = "960x540";
  int every = 0;       // 0 = about 250 frames over the run
  std::string outDir;  // default RUN_DIR/frames
  int sheetCells = 12;
  int thumbWidth = 320;
  bool noFrames = false;
  bool noVideo = false;
  int supersample = 2;
  bool groundContacts = false;
  double depthScale = 0.005;                 // m
  std::string cache;                         // haptic runs: model cache of fields built from meshes
  const CLI::Option* cacheOption = nullptr;  // given: --cache wins, even "" (no cache)
};

#if SDFCCD_HAS_RENDER

/// True for a haptic run folder (ticks.csv, no frames.csv) in a build with the haptics module.
bool isHapticRun(const RenderOptions& options) {
#if SDFCCD_HAS_HAPTICS
  return isHapticRunFolder(options.runDir);
#else
  (void)options;
  return false;
#endif
}

/// A simulate run (frames.csv), or a haptic run (ticks.csv: the tool at its recorded poses and the obstacle).
RunFolder readAnyRunFolder(const RenderOptions& options) {
#if SDFCCD_HAS_HAPTICS
  if (isHapticRun(options)) {
    return readHapticRunFolder(options.runDir,
                               modelCacheFolder(options.cacheOption->count() > 0 ? &options.cache : nullptr));
  }
#endif
  return readRunFolder(options.runDir);
}

/// The corners of every body's box at every pose of the run: what automatic framing must keep in view.
std::vector<Vec3> runFramingPoints(const RunScene& scene, const RunFrames& frames) {
  std::vector<Box3> localBoxes;
  for (const RunBody& body : scene.bodies) {
    Box3 box;
    for (const Vec3& v : body.mesh->vertices) box.extend(v);  // scaled, body frame
    localBoxes.push_back(box);
  }
  std::vector<Vec3> points;
  for (const std::vector<Rigid>& poses : frames.worldFromBody) {
    for (std::size_t i = 0; i < poses.size(); ++i) {
      for (int corner = 0; corner < 8; ++corner) {
        points.push_back(poses[i] * localBoxes[i].corner(static_cast<Box3::CornerType>(corner)));
      }
    }
  }
  return points;
}

/// Mesh vertices below the ground, as contacts coloured by depth: a body sunk into the ground shows red.
std::vector<FramePoints> groundContacts(const RunScene& scene, const std::vector<Rigid>& poses, double depthScale) {
  FramePoints contacts;
  contacts.maxDepth = depthScale;
  if (!scene.groundHeight) return {};
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    for (const Vec3& vertexInBody : scene.bodies[i].mesh->vertices) {
      const Vec3 vertexInWorld = poses[i] * vertexInBody;
      const double depth = *scene.groundHeight - vertexInWorld.y();
      if (depth > 0.0) {
        contacts.pointsInWorld.push_back(vertexInWorld);
        contacts.depths.push_back(depth);
      }
    }
  }
  return {contacts};
}

/// Writes outDir/frames.mp4 from the frames written, when ffmpeg is on PATH. Returns a one-line note.
std::string writeVideo(const std::vector<std::string>& framePaths, double framesPerSecond,
                       const std::string& videoPath) {
  const std::optional<std::string> ffmpeg = findProgram("ffmpeg");
  if (!ffmpeg) return "no MP4: ffmpeg is not installed (Debian: apt-get install ffmpeg)";
  // ffmpeg writes in a private scratch folder (it opens its output by name, following links); the video then
  // goes to its place through OutputFile. The concat list names exactly the frames of this render (older
  // frames in the folder are left out).
  ScratchFolder scratch;
  const std::string listPath = scratch.file("frames.txt");
  std::string list = "ffconcat version 1.0\n";
  char duration[64];
  std::snprintf(duration, sizeof(duration), "duration %.6f\n", 1.0 / framesPerSecond);
  for (const std::string& path : framePaths) list += "file '" + fs::absolute(path).string() + "'\n" + duration;
  if (!framePaths.empty()) list += "file '" + fs::absolute(framePaths.back()).string() + "'\n";
  writeOutputFile(listPath, list);
  const std::string temporary = scratch.file("frames.mp4");
  const ProgramRun run = runProgram({*ffmpeg, "-y", "-loglevel", "error", "-f", "concat", "-safe", "0", "-i", listPath,
                                     "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2,fps=" + std::to_string(framesPerSecond),
                                     "-c:v", "libx264", "-pix_fmt", "yuv420p", "-movflags", "+faststart", temporary},
                                    scratch.file("ffmpeg.log"));
  if (run.exitCode != 0) {
    // The video is optional: the frames and the sheet are written, so a failing ffmpeg is a warning only.
    try {
      moveToOutput(scratch.file("ffmpeg.log"), videoPath + ".log");
    } catch (const Error&) {
    }
    return "warning: no MP4: ffmpeg failed (exit " + std::to_string(run.exitCode) + "): " + run.logTail +
           " (log: " + videoPath + ".log)";
  }
  moveToOutput(temporary, videoPath);
  return "video: " + videoPath;
}

int runRender(const RenderOptions& options) {
  int width = 0;
  int height = 0;
  parseImageSize(options.size, width, height);
  if (options.every < 0) throw Error("--every must be at least 1");
  if (!(options.depthScale > 0.0) || !std::isfinite(options.depthScale)) throw Error("--depth-scale must be > 0");
  if (options.sheetCells < 0 || options.thumbWidth < 16 || options.thumbWidth > 4096) {
    throw Error("--sheet-cells must be >= 0 and --thumb-width in 16..4096");
  }
  const RunFolder run = readAnyRunFolder(options);
  const RunFrames& frames = run.frames;
  const int frameCount = static_cast<int>(frames.times.size());
  const int every = options.every > 0 ? options.every : std::max(1, (frameCount + 249) / 250);

  FrameRenderSettings settings = frameRenderSettingsFor(run.scene);
  settings.width = width;
  settings.height = height;
  settings.every = every;
  settings.supersample = options.supersample;
  if (!settings.camera) settings.framingPoints = runFramingPoints(run.scene, frames);
  if (isHapticRun(options)) {
    // A haptic run: its scenes are centimetres across, below the 0.1 m that automatic framing keeps at least.
    render::CameraFramingSettings framing;
    framing.minimumSize = 1e-3;
    const render::RenderCamera camera =
        render::framePoints(settings.framingPoints, static_cast<double>(width) / height, framing);
    settings.camera = SceneCamera{camera.eye, camera.target, camera.up, camera.fovDegrees};
  }
  RunFrameRenderer renderer(run.scene.bodies, settings);

  const std::string outDir = options.outDir.empty() ? (fs::path(options.runDir) / "frames").string() : options.outDir;
  std::vector<std::string> written;
  if (!options.noFrames) {
    std::error_code error;
    fs::create_directories(outDir, error);
    if (error) throw Error("cannot create the frames folder '" + outDir + "': " + error.message());
    // Frames whose number is a multiple of K, as `simulate --render --every K` names them; rows in steps of K
    // when the numbering has no such frames.
    std::vector<int> rows;
    for (int i = 0; i < frameCount; ++i) {
      if (frames.frameNumbers[static_cast<std::size_t>(i)] % every == 0) rows.push_back(i);
    }
    if (rows.empty()) {
      for (int i = 0; i < frameCount; i += every) rows.push_back(i);
    }
    ProgressBar bar("rendering frames");
    for (int i : rows) {
      const std::vector<Rigid>& poses = frames.worldFromBody[static_cast<std::size_t>(i)];
      renderer.renderToFile(
          poses, RunFrameRenderer::framePath(outDir, frames.frameNumbers[static_cast<std::size_t>(i)]),
          options.groundContacts ? groundContacts(run.scene, poses, options.depthScale) : std::vector<FramePoints>{});
      written.push_back(RunFrameRenderer::framePath(outDir, frames.frameNumbers[static_cast<std::size_t>(i)]));
      bar.update(static_cast<double>(i + 1) / frameCount);
    }
    bar.finish();
    std::printf("frames: %zu PNG (%dx%d, every %d of %d frames) in %s\n", written.size(), width, height, every,
                frameCount, outDir.c_str());
  }

  if (options.sheetCells > 0) {
    const int thumbHeight =
        std::max(1, static_cast<int>(std::lround(static_cast<double>(options.thumbWidth) * height / width)));
    std::vector<render::RgbImage> thumbs;
    for (int index : render::evenlySpacedFrames(frameCount, options.sheetCells)) {
      const std::vector<Rigid>& poses = frames.worldFromBody[static_cast<std::size_t>(index)];
      thumbs.push_back(renderer.renderImage(
          poses,
          options.groundContacts ? groundContacts(run.scene, poses, options.depthScale) : std::vector<FramePoints>{},
          options.thumbWidth, thumbHeight));
    }
    const std::string sheetPath = (fs::path(options.runDir) / "contact_sheet.png").string();
    render::writePng(sheetPath, render::makeContactSheet(thumbs));
    std::printf("contact sheet: %s (%zu frames, left to right, top to bottom)\n", sheetPath.c_str(), thumbs.size());
  }

  if (!options.noFrames && !options.noVideo && written.size() >= 2) {
    // Real time when the frame times allow it, kept between 1 and 60 frames per second.
    double framesPerSecond = 30.0;
    const double span = frames.times.back() - frames.times.front();
    if (span > 0.0) framesPerSecond = std::clamp((frameCount - 1) / span / every, 1.0, 60.0);
    std::printf("%s\n", writeVideo(written, framesPerSecond, (fs::path(outDir) / "frames.mp4").string()).c_str());
  }
  return 0;
}

#else

int runRender(const RenderOptions&) {
  throw Error("this sdfccd was built without the renderer (-DSDFCCD_BUILD_RENDER=OFF)");
}

#endif

const CommandRegistrar cmd_renderRegistrar("render", [](CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render a saved run's frames, contact sheet and MP4 (no re-simulation)");
  cmd->add_option("run_dir", options->runDir, "Run folder written by `sdfccd simulate --out` or `sdfccd haptics --out`")
      ->required();
  cmd->add_option("--size", options->size, "Frame size WIDTHxHEIGHT (default 960x540)");
  cmd->add_option("--every", options->every, "Render every K-th frame (default: about 250 frames in all)");
  cmd->add_option("--out", options->outDir, "Folder for the frames (default RUN_DIR/frames)");
  cmd->add_option("--sheet-cells", options->sheetCells, "Frames on the contact sheet (0 = no sheet; default 12)");
  cmd->add_option("--thumb-width", options->thumbWidth, "Width of a contact-sheet frame in pixels (default 320)");
  cmd->add_option("--supersample", options->supersample, "Anti-aliasing factor, 1 = none (default 2)");
  cmd->add_flag("--no-frames", options->noFrames, "Only the contact sheet");
  cmd->add_flag("--ground-contacts", options->groundContacts,
                "Mark mesh vertices below the ground, yellow to red by depth (a sunk body shows red)");
  cmd->add_option("--depth-scale", options->depthScale, "With --ground-contacts: depth drawn fully red (m, 0.005)");
  cmd->add_flag("--no-video", options->noVideo, "No MP4 even when ffmpeg is installed");
  options->cacheOption = cmd->add_option("--cache", options->cache,
                                         "Haptic runs: cache of fields built from meshes (\"\" disables; default as "
                                         "sdfccd haptics)");
  return std::function<int()>([options]() { return runRender(*options); });
});

}  // namespace
}  // namespace sdfccd::cli
