/// @file
/// @brief Sections of `sdfccd report` register themselves here (what accuracy costs in time, and hard cases that
/// stay stable).
///
/// @details Same pattern as bench_registry.h. Each demos/report/<id>.cpp defines a static ReportRegistrar; the
/// report command (cmd_report.cpp) runs the sections in `order`, shows progress on stderr, and joins their
/// Markdown into DIR/report.md. A section writes its CSV and PNG files into context.outDir, their names
/// prefixed by the section's id, and links them by relative path. Every table states the paper's figure beside
/// ours; the machine is stated once at the top of the report. Files named demos/report/bullet_*.cpp or
/// haptics_*.cpp are left out of builds without that module.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace sdfccd::cli {

/// What a section gets.
struct ReportContext {
  std::filesystem::path outDir;     ///< DIR of `--out`; exists when the section runs
  std::filesystem::path assetsDir;  ///< the project's assets/ (meshes, scenes)
  std::filesystem::path cacheDir;   ///< the model cache (--cache; default $XDG_CACHE_HOME/sdfccd); "": none
  bool quick = false;               ///< `--quick`: the whole report in a few minutes
  bool smoke = false;  ///< hidden `--smoke` (tests): quick with the smallest counts that still mean something
  int threads = 1;     ///< worker threads a section may use (timings are one core unless stated)
  std::function<void(double)> progress;  ///< fraction of this section done, in [0, 1] (never null)
};

/// What a section returns.
struct ReportSection {
  std::string markdown;  ///< starts with "## <title>"; tables, findings, image links (relative to outDir)
  bool ok = true;        ///< false when a stated target or expected outcome was not met (the report says so)
};

using ReportRunner = std::function<ReportSection(const ReportContext&)>;

struct ReportEntry {
  int order;          ///< sections appear in increasing order
  std::string id;     ///< short name: `--only id`, file prefix
  std::string title;  ///< shown in the progress lines
  ReportRunner run;
};

inline std::vector<ReportEntry>& reportRegistry() {
  static std::vector<ReportEntry> registry;
  return registry;
}

struct ReportRegistrar {
  ReportRegistrar(int order, std::string id, std::string title, ReportRunner run) {
    reportRegistry().push_back({order, std::move(id), std::move(title), std::move(run)});
  }
};

}  // namespace sdfccd::cli
