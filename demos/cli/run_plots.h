/// @file
/// @brief writeRunPlots: PNG plots of a saved run (penetration, kinetic energy, contacts, CCD time per frame)
/// drawn by gnuplot from a generated script.
///
/// @details gnuplot (Debian gnuplot-nox) draws the axes, ticks and labels; the tool only writes the data and a
/// script, both kept in RUN_DIR/plots/ so a user can re-run or edit them (`gnuplot plots.gp`). The pngcairo
/// terminal is used when gnuplot has it (anti-aliased), the libgd png terminal otherwise; both work headless.
/// Each PNG is written under a temporary name and renamed when gnuplot succeeded, so a failure leaves no
/// half-written picture.
#pragma once

#include <string>
#include <vector>

#include "cli/run_folder.h"

namespace sdfccd::cli {

/// Sizes and places of the plots.
struct RunPlotSettings {
  int width = 900;                               ///< pixels of one plot
  int height = 420;                              ///< pixels of one plot
  std::string outputDir;                         ///< default RUN_DIR/plots
  std::string rowName = "frame";                 ///< what one row is, in titles ("tick" for haptic runs)
  std::string timeLabel = "simulated time (s)";  ///< the x axis
};

/// What writeRunPlots made.
struct RunPlotResult {
  std::vector<std::string> written;  ///< PNG files, one per series found, then overview.png
  std::vector<std::string> skipped;  ///< series the CSV does not have (one line each, for the user)
};

/// Plots the series of `frames` into settings.outputDir. Throws sdfccd::Error when gnuplot is not installed,
/// when the run has none of the series, or when gnuplot fails (quoting its last output lines).
RunPlotResult writeRunPlots(const RunFrames& frames, const RunPlotSettings& settings);

}  // namespace sdfccd::cli
