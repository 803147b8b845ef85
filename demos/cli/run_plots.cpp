/// @file
/// @brief writeRunPlots: series.dat + plots.gp, run through gnuplot.
#include "cli/run_plots.h"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cli/external_program.h"
#include "cli/line_plot.h"
#include "cli/scratch_folder.h"
#include "sdfccd/error.h"
#include "sdfccd/output_file.h"

namespace sdfccd::cli {

namespace fs = std::filesystem;

namespace {

struct PlotSpec {
  const char* series;  // key in RunFrames::series
  const char* file;    // PNG name
  const char* title;
  const char* yLabel;
  const char* color;
};

const PlotSpec kPlots[] = {
    {"penetration", "penetration.png", "Deepest penetration per frame", "penetration", "#d62728"},
    {"kinetic_energy", "kinetic_energy.png", "Kinetic energy per frame", "kinetic energy (J)", "#1f77b4"},
    {"contacts", "contacts.png", "Contacts per frame", "contact count", "#2ca02c"},
    {"ccd_seconds", "ccd_time.png", "CCD time per frame", "CCD time (ms)", "#9467bd"},
    // Haptic runs only (haptic_run.h): magnitudes of the force and torque on the device per tick.
    {"force", "force.png", "Force on the device per frame", "force (N)", "#ff7f0e"},
    {"torque", "torque.png", "Torque on the device per frame", "torque (N m)", "#8c564b"},
};

}  // namespace

RunPlotResult writeRunPlots(const RunFrames& frames, const RunPlotSettings& settings) {
  const std::optional<std::string> gnuplot = findProgram("gnuplot");
  if (!gnuplot) {
    throw Error("gnuplot is not installed: plots need it (Debian: apt-get install gnuplot-nox)");
  }
  if (settings.width < 64 || settings.height < 64 || settings.width > 8192 || settings.height > 8192) {
    throw Error("plot size must be between 64x64 and 8192x8192");
  }
  if (frames.times.empty()) throw Error("the run has no frames to plot");
  RunPlotResult result;
  std::vector<const PlotSpec*> present;
  for (const PlotSpec& plot : kPlots) {
    if (frames.series.count(plot.series) != 0) {
      present.push_back(&plot);
    } else if (std::string(plot.series) != "force" && std::string(plot.series) != "torque") {
      result.skipped.push_back(std::string(plot.series) + ": no such column in the frames CSV");
    }
  }
  if (present.empty()) {
    throw Error("the frames CSV has none of the columns contacts, penetration, kinetic_energy, ccd_seconds");
  }
  const std::string dir = settings.outputDir;
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw Error("cannot create the plots folder '" + dir + "': " + error.message());

  // Data: one row per frame: frame, time, then the series in kPlots order (CCD time in milliseconds).
  std::ostringstream data;
  data.precision(10);
  data << "# frame time";
  for (const PlotSpec* plot : present) data << ' ' << plot->series;
  data << '\n';
  for (std::size_t i = 0; i < frames.times.size(); ++i) {
    data << frames.frameNumbers[i] << ' ' << frames.times[i];
    for (const PlotSpec* plot : present) {
      const double value = frames.series.at(plot->series)[i];
      data << ' ' << (std::string(plot->series) == "ccd_seconds" ? 1e3 * value : value);
    }
    data << '\n';
  }
  const std::string dataPath = (fs::path(dir) / "series.dat").string();
  writeOutputFile(dataPath, data.str());

  // gnuplot draws into a private scratch folder (it opens outputs by name, following links); the PNGs then go
  // to their places through OutputFile. The script kept in the plots folder is the same with the PNGs' own
  // folder: `gnuplot plots.gp` draws them again.
  ScratchFolder scratch;
  const std::string terminal = gnuplotPngTerminal(*gnuplot, settings.width, settings.height, scratch.path());
  const int rows = (static_cast<int>(present.size()) + 1) / 2;
  const std::string overviewTerminal =
      gnuplotPngTerminal(*gnuplot, settings.width * 2, settings.height * rows, scratch.path());
  // The penetration's unit follows its column: `penetration_m` is in metres; `penetration` and
  // `penetration_cells` are in grid cells of the field (what simulate reports, like max_penetration_cells).
  auto yLabel = [&](const PlotSpec* plot) -> std::string {
    if (std::string(plot->series) != "penetration") return plot->yLabel;
    auto source = frames.seriesSource.find("penetration");
    const bool metres = source != frames.seriesSource.end() && source->second.find("_m") != std::string::npos;
    return metres ? "penetration (m)" : "penetration (grid cells)";
  };
  // "... per frame", or per the run's own row (a haptic run's tick).
  auto title = [&](const PlotSpec* plot) {
    std::string text = plot->title;
    const std::size_t at = text.rfind(" per frame");
    if (at != std::string::npos) text = text.substr(0, at) + " per " + settings.rowName;
    return text;
  };
  auto makeScript = [&](const std::string& pngFolder) {
    std::ostringstream script;
    script << terminal << "set datafile commentschars '#'\nset grid\nset key off\nset xlabel "
           << gnuplotQuoted(settings.timeLabel) << "\n"
           << "set style line 1 linewidth 1.5\n";
    int column = 3;
    for (const PlotSpec* plot : present) {
      script << "set output " << gnuplotQuoted((fs::path(pngFolder) / plot->file).string()) << "\nset title "
             << gnuplotQuoted(title(plot)) << "\nset ylabel " << gnuplotQuoted(yLabel(plot)) << "\nplot "
             << gnuplotQuoted(dataPath) << " using 2:" << column << " with lines linewidth 1.5 linecolor rgb '"
             << plot->color << "'\nunset output\n";
      ++column;
    }
    // All series on one page.
    script << overviewTerminal << "set output " << gnuplotQuoted((fs::path(pngFolder) / "overview.png").string())
           << "\nset multiplot layout " << rows << ",2\n";
    column = 3;
    for (const PlotSpec* plot : present) {
      script << "set title " << gnuplotQuoted(title(plot)) << "\nset ylabel " << gnuplotQuoted(yLabel(plot))
             << "\nplot " << gnuplotQuoted(dataPath) << " using 2:" << column
             << " with lines linewidth 1.5 linecolor rgb '" << plot->color << "'\n";
      ++column;
    }
    script << "unset multiplot\nunset output\n";
    return script.str();
  };
  const std::string scriptPath = (fs::path(dir) / "plots.gp").string();
  writeOutputFile(scriptPath,
                  "# Generated by `sdfccd plot`; draw again with: gnuplot plots.gp (from this folder's "
                  "parent or here)\n" +
                      makeScript(dir));
  const std::string runScript = scratch.file("plots.gp");
  writeOutputFile(runScript, makeScript(scratch.path()));
  std::vector<std::pair<std::string, std::string>> moves;  // scratch -> final
  for (const PlotSpec* plot : present)
    moves.emplace_back(scratch.file(plot->file), (fs::path(dir) / plot->file).string());
  moves.emplace_back(scratch.file("overview.png"), (fs::path(dir) / "overview.png").string());

  const ProgramRun run = runProgram({*gnuplot, runScript}, scratch.file("gnuplot.log"));
  if (run.exitCode != 0) throw Error("gnuplot failed (exit " + std::to_string(run.exitCode) + "): " + run.logTail);
  for (const auto& [temporary, finalPath] : moves) {
    if (!fs::exists(temporary)) throw Error("gnuplot did not write '" + finalPath + "'");
    moveToOutput(temporary, finalPath);
    result.written.push_back(finalPath);
  }
  return result;
}

}  // namespace sdfccd::cli
