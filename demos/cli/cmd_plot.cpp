/// @file
/// @brief `sdfccd plot RUN_DIR`: PNG plots of penetration, kinetic energy, contacts and CCD time per frame; of a
/// haptic run folder (`sdfccd haptics --out`, haptic_run.h): force and torque magnitude, contacts and penetration
/// per tick.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/command_registry.h"
#if SDFCCD_HAS_HAPTICS
#include "cli/haptic_run.h"
#endif
#include "cli/run_frame_renderer.h"
#include "cli/run_plots.h"
#include "sdfccd/error.h"

namespace sdfccd::cli {
namespace {

struct PlotOptions {
  std::string runDir;
  std::string size = "900x420";
  std::string outDir;
};

int runPlot(const PlotOptions& options) {
  RunPlotSettings settings;
  parseImageSize(options.size, settings.width, settings.height);
  settings.outputDir =
      options.outDir.empty() ? (std::filesystem::path(options.runDir) / "plots").string() : options.outDir;
#if SDFCCD_HAS_HAPTICS
  if (isHapticRunFolder(options.runDir)) {
    // A haptic run: force and torque magnitudes, contacts and penetration per tick (no scene needed).
    RunFrames ticks = readHapticTicks(options.runDir);
    settings.rowName = "tick";
    settings.timeLabel = "session time (s)";
    const RunPlotResult result = writeRunPlots(ticks, settings);
    for (const std::string& path : result.written) std::printf("plot: %s\n", path.c_str());
    return 0;
  }
#endif
  // Meshes are needed only to compute the kinetic energy when the CSV has no column for it.
  RunFolder run = readRunFolder(options.runDir, /*loadMeshes=*/false);
  if (run.frames.series.count("kinetic_energy") == 0) {
    try {
      run = readRunFolder(options.runDir, /*loadMeshes=*/true);
    } catch (const Error& e) {
      std::printf("note: no kinetic energy (the CSV has none and the meshes could not be loaded: %s)\n", e.what());
    }
  }
  const RunPlotResult result = writeRunPlots(run.frames, settings);
  for (const std::string& path : result.written) std::printf("plot: %s\n", path.c_str());
  for (const std::string& note : result.skipped) std::printf("skipped %s\n", note.c_str());
  return 0;
}

const CommandRegistrar cmd_plotRegistrar("plot", [](CLI::App& app) {
  auto options = std::make_shared<PlotOptions>();
  CLI::App* cmd = app.add_subcommand("plot", "Plot a saved run: penetration, kinetic energy, contacts, CCD time");
  cmd->add_option("run_dir", options->runDir, "Run folder written by `sdfccd simulate --out` or `sdfccd haptics --out`")
      ->required();
  cmd->add_option("--size", options->size, "Size of one plot WIDTHxHEIGHT (default 900x420)");
  cmd->add_option("--out", options->outDir, "Folder for the plots (default RUN_DIR/plots)");
  return std::function<int()>([options]() { return runPlot(*options); });
});

}  // namespace
}  // namespace sdfccd::cli
