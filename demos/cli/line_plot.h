/// @file
/// @brief writeLinePlot: one PNG chart (lines, points or bars) drawn by gnuplot from the given series, for the
/// report and the benchmarks.
///
/// @details gnuplot (Debian gnuplot-nox) draws axes, ticks, labels and the legend; we only write the data and
/// a script, kept beside the PNG (`NAME.dat`, `NAME.gp`) so a reader can redraw or restyle it. The PNG is
/// written under a temporary name and renamed when gnuplot succeeded: a failure leaves no half-written image.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace sdfccd::cli {

enum class PlotStyle { Lines, Points, LinesPoints, Bars };

/// One curve (or one set of bars).
struct PlotSeries {
  std::string label;      ///< legend entry
  std::vector<double> x;  ///< abscissae (ignored for bars with categories)
  std::vector<double> y;  ///< ordinates, same length as x (or as the categories); NaN leaves a gap
};

struct LinePlot {
  std::string title;
  std::string xLabel;
  std::string yLabel;
  bool logX = false;
  bool logY = false;
  PlotStyle style = PlotStyle::LinesPoints;
  std::vector<std::string> categories;  ///< for bars: one label per bar group (x values are then ignored)
  std::vector<PlotSeries> series;
  std::string legend = "top left";  ///< where the legend goes (gnuplot `set key`), e.g. "outside right top"
  int width = 800;                  ///< pixels
  int height = 450;                 ///< pixels
};

/// Draws `plot` into `pngPath`. Throws sdfccd::Error when gnuplot is missing, the plot is empty or malformed
/// (series of unequal lengths, non-positive values on a log axis), or gnuplot fails (quoting its output).
void writeLinePlot(const LinePlot& plot, const std::filesystem::path& pngPath);

/// gnuplot's single-quoted string for `text`.
std::string gnuplotQuoted(const std::string& text);

/// "set terminal ..." for a PNG of the given size: pngcairo when this gnuplot has it, else the libgd png.
std::string gnuplotPngTerminal(const std::string& gnuplot, int width, int height,
                               const std::filesystem::path& scratchDir);

}  // namespace sdfccd::cli
