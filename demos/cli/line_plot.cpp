/// @file
/// @brief writeLinePlot: NAME.dat + NAME.gp beside the PNG, run through gnuplot.
#include "cli/line_plot.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "cli/external_program.h"
#include "cli/scratch_folder.h"
#include "sdfccd/error.h"
#include "sdfccd/output_file.h"

namespace sdfccd::cli {

namespace fs = std::filesystem;

std::string gnuplotQuoted(const std::string& text) {
  std::string result = "'";
  for (char c : text) {
    if (c == '\'')
      result += "''";  // gnuplot's single-quote escape
    else if (c == '\n')
      result += ' ';
    else
      result += c;
  }
  return result + "'";
}

std::string gnuplotPngTerminal(const std::string& gnuplot, int width, int height, const fs::path& scratchDir) {
  const std::string probe = (scratchDir / ".probe.gp").string();
  const std::string log = (scratchDir / ".probe.log").string();
  writeOutputFile(probe, "set terminal pngcairo\n");
  const ProgramRun run = runProgram({gnuplot, probe}, log);
  std::error_code ignored;
  fs::remove(probe, ignored);
  fs::remove(log, ignored);
  const bool cairo = run.exitCode == 0 && run.logTail.find("unknown") == std::string::npos;
  char terminal[160];
  std::snprintf(terminal, sizeof(terminal), "set terminal %s size %d,%d%s\n", cairo ? "pngcairo" : "png", width, height,
                cairo ? " enhanced font 'sans,10'" : "");
  return terminal;
}

namespace {

void validate(const LinePlot& plot) {
  if (plot.series.empty()) throw Error("plot '" + plot.title + "' has no series");
  // The legend placement goes into the script as it is: gnuplot words only.
  for (const char c : plot.legend) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != ' ' && c != ',' && c != '.' && c != '-') {
      throw Error("plot '" + plot.title + "': bad legend placement '" + plot.legend + "'");
    }
  }
  if (plot.width < 64 || plot.height < 64 || plot.width > 8192 || plot.height > 8192) {
    throw Error("plot size must be between 64x64 and 8192x8192");
  }
  const bool categorical = plot.style == PlotStyle::Bars && !plot.categories.empty();
  for (const PlotSeries& series : plot.series) {
    const std::size_t expected = categorical ? plot.categories.size() : series.x.size();
    if (series.y.size() != expected || series.y.empty()) {
      throw Error("plot '" + plot.title + "': series '" + series.label + "' has " + std::to_string(series.y.size()) +
                  " values for " + std::to_string(expected) + " abscissae");
    }
    for (std::size_t i = 0; i < series.y.size(); ++i) {
      const double x = categorical ? 1.0 : series.x[i];
      const double y = series.y[i];
      if (std::isinf(x) || std::isinf(y) || std::isnan(x)) {
        throw Error("plot '" + plot.title + "': series '" + series.label + "' has a non-finite value");
      }
      if ((plot.logX && !(x > 0.0)) || (plot.logY && !std::isnan(y) && !(y > 0.0))) {
        throw Error("plot '" + plot.title + "': series '" + series.label + "' has a value <= 0 on a log axis");
      }
    }
  }
}

const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#7f7f7f"};

}  // namespace

void writeLinePlot(const LinePlot& plot, const fs::path& pngPath) {
  validate(plot);
  const std::optional<std::string> gnuplot = findProgram("gnuplot");
  if (!gnuplot) throw Error("gnuplot is not installed: plots need it (Debian: apt-get install gnuplot-nox)");
  const fs::path dir = pngPath.has_parent_path() ? pngPath.parent_path() : fs::path(".");
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw Error("cannot create the folder '" + dir.string() + "': " + error.message());

  const bool categorical = plot.style == PlotStyle::Bars && !plot.categories.empty();
  // Data: one gnuplot block per series (blocks separated by two blank lines, addressed with `index`).
  std::ostringstream data;
  data.precision(12);
  for (std::size_t s = 0; s < plot.series.size(); ++s) {
    const PlotSeries& series = plot.series[s];
    data << "# " << series.label << '\n';
    for (std::size_t i = 0; i < series.y.size(); ++i) {
      if (categorical) {
        data << i << ' ';
        if (std::isnan(series.y[i]))
          data << "NaN";
        else
          data << series.y[i];
        data << '\n';
      } else {
        data << series.x[i] << ' ';
        if (std::isnan(series.y[i]))
          data << "NaN";
        else
          data << series.y[i];
        data << '\n';
      }
    }
    data << "\n\n";
  }
  fs::path dataPath = pngPath;
  dataPath.replace_extension(".dat");
  writeOutputFile(dataPath.string(), data.str());

  // gnuplot draws into a private scratch folder (it opens its output by name, following links); the PNG
  // then goes to its place through OutputFile. The script kept beside the PNG names the PNG itself.
  ScratchFolder scratch;
  const std::string temporary = scratch.file("plot.png");
  const std::string terminal = gnuplotPngTerminal(*gnuplot, plot.width, plot.height, scratch.path());
  std::ostringstream script;
  script << "\nset title " << gnuplotQuoted(plot.title) << "\nset xlabel " << gnuplotQuoted(plot.xLabel)
         << "\nset ylabel " << gnuplotQuoted(plot.yLabel) << "\nset grid\nset key " << plot.legend << "\n"
         << "set datafile missing 'NaN'\n";
  if (plot.logX) script << "set logscale x\n";
  if (plot.logY) script << "set logscale y\n";
  if (plot.series.size() == 1 && plot.series[0].label.empty()) script << "set key off\n";
  const std::string dataFile = gnuplotQuoted(dataPath.string());
  if (categorical) {
    const double groups = static_cast<double>(plot.series.size());
    const double width = 0.8 / groups;
    script << "set style fill solid 0.8 border -1\nset boxwidth " << width
           << "\nset xrange [-0.6:" << (static_cast<double>(plot.categories.size()) - 0.4) << "]\nset xtics (";
    for (std::size_t i = 0; i < plot.categories.size(); ++i) {
      script << (i ? ", " : "") << gnuplotQuoted(plot.categories[i]) << ' ' << i;
    }
    script << ")\nset yrange [0:*]\nplot ";
    for (std::size_t s = 0; s < plot.series.size(); ++s) {
      const double offset = (static_cast<double>(s) - (groups - 1.0) / 2.0) * width;
      script << (s ? ", " : "") << dataFile << " index " << s << " using ($1+" << offset
             << "):2 with boxes linecolor rgb '" << kColors[s % 8] << "' title " << gnuplotQuoted(plot.series[s].label);
    }
  } else {
    const char* with = plot.style == PlotStyle::Lines    ? "lines linewidth 1.5"
                       : plot.style == PlotStyle::Points ? "points pointtype 7 pointsize 0.8"
                       : plot.style == PlotStyle::Bars   ? "boxes"
                                                         : "linespoints linewidth 1.5 pointtype 7 pointsize 0.8";
    script << "plot ";
    for (std::size_t s = 0; s < plot.series.size(); ++s) {
      script << (s ? ", " : "") << dataFile << " index " << s << " using 1:2 with " << with << " linecolor rgb '"
             << kColors[s % 8] << "' title " << gnuplotQuoted(plot.series[s].label);
    }
  }
  script << "\nunset output\n";
  fs::path scriptPath = pngPath;
  scriptPath.replace_extension(".gp");
  writeOutputFile(scriptPath.string(), "# Generated by sdfccd; redraw with: gnuplot " + pngPath.stem().string() +
                                           ".gp\n" + terminal + "set output " + gnuplotQuoted(pngPath.string()) +
                                           script.str());
  const std::string runScript = scratch.file("plot.gp");
  writeOutputFile(runScript, terminal + "set output " + gnuplotQuoted(temporary) + script.str());

  const ProgramRun run = runProgram({*gnuplot, runScript}, scratch.file("gnuplot.log"));
  if (run.exitCode != 0 || !fs::exists(temporary)) {
    throw Error("gnuplot failed on '" + scriptPath.string() + "' (exit " + std::to_string(run.exitCode) +
                "): " + run.logTail);
  }
  moveToOutput(temporary, pngPath.string());
}

}  // namespace sdfccd::cli
