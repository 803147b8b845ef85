/// @file
/// @brief `sdfccd report [--quick] --out DIR [--only id,...] [--assets DIR] [--cache DIR] [--threads N]`: runs the
/// registered report sections (report_registry.h: what accuracy costs in time, hard cases that stay stable,
/// effects that cost nothing when off) and writes DIR/report.md and DIR/report.json.
///
/// @details Sections run in their registered order, each announced on stderr ("report [2/6] <title>") with a
/// progress bar fed by the section's callback. A section that throws is reported as failed (one line with the
/// message) and the others still run; the command then exits 1 after writing the report. A section that returns
/// ok = false (a stated target not met) is marked "no" in the summary: that is a finding, not a tool failure,
/// and the exit code stays 0. report.md and report.json are written atomically once every section has run.
/// The hidden flag `--smoke` (tests) is quick mode with the smallest counts that still mean something.
///
/// The assets folder: --assets, else ./assets, else the source tree's assets recorded at build time
/// (SDFCCD_SOURCE_ASSETS_DIR), else an error asking for --assets.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bench/cache_option.h"
#include "bench/option_checks.h"
#include "cli/bench_registry.h"
#include "cli/command_registry.h"
#include "cli/progress_bar.h"
#include "cli/report_registry.h"
#include "sdfccd/error.h"
#include "sdfccd/output_file.h"
#include "sdfccd/output_folder.h"
#include "sdfccd/parallel_for.h"

#ifndef SDFCCD_BUILD_TYPE
#define SDFCCD_BUILD_TYPE "unknown"
#endif

namespace sdfccd::cli {
namespace {

namespace fs = std::filesystem;

struct ReportOptions {
  bool quick = false;
  bool smoke = false;
  std::string out;
  std::string only;
  std::string assets;
  std::string cache;  // resolved by resolveCacheOption before the run
  int threads = 0;    // 0 (not given): all hardware threads
  bool threadsGiven = false;
};

/// What happened to one section.
struct SectionOutcome {
  const ReportEntry* entry = nullptr;
  ReportSection section;
  bool failed = false;  // threw: section.markdown holds the one-line message
  std::string error;
  double seconds = 0.0;  // wall time
};

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  for (std::string item; std::getline(stream, item, ',');) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

/// The registered sections in order, restricted to `only` (empty: all). Unknown ids are an error.
std::vector<const ReportEntry*> selectSections(const std::string& only) {
  std::vector<ReportEntry>& registry = reportRegistry();
  std::stable_sort(registry.begin(), registry.end(),
                   [](const ReportEntry& a, const ReportEntry& b) { return a.order < b.order; });
  std::string known;
  for (const ReportEntry& e : registry) known += (known.empty() ? "" : ", ") + e.id;
  std::vector<const ReportEntry*> selected;
  if (only.empty()) {
    for (const ReportEntry& e : registry) selected.push_back(&e);
    return selected;
  }
  const std::vector<std::string> ids = splitList(only);
  if (ids.empty()) throw Error("--only lists no section (known: " + known + ")");
  for (const std::string& id : ids) {
    const auto it = std::find_if(registry.begin(), registry.end(), [&](const ReportEntry& e) { return e.id == id; });
    if (it == registry.end()) throw Error("--only: unknown section '" + id + "' (known: " + known + ")");
  }
  for (const ReportEntry& e : registry) {
    if (std::find(ids.begin(), ids.end(), e.id) != ids.end()) selected.push_back(&e);
  }
  return selected;
}

bool looksLikeAssets(const fs::path& dir) {
  std::error_code ec;
  return fs::is_directory(dir / "meshes", ec) && fs::is_directory(dir / "scenes", ec);
}

fs::path findAssets(const std::string& given) {
  if (!given.empty()) {
    if (!looksLikeAssets(given)) throw Error("--assets '" + given + "' has no meshes/ and scenes/ folders");
    return fs::absolute(given);
  }
  if (looksLikeAssets("assets")) return fs::absolute("assets");
#ifdef SDFCCD_SOURCE_ASSETS_DIR
  if (looksLikeAssets(SDFCCD_SOURCE_ASSETS_DIR)) return fs::path(SDFCCD_SOURCE_ASSETS_DIR);
#endif
  throw Error("no assets folder found (./assets or the source tree's): pass --assets DIR");
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M UTC", &utc);
  return text;
}

std::string buildDescription() {
  std::string build = SDFCCD_BUILD_TYPE;
  if (build.empty()) build = "unspecified";
#ifndef NDEBUG
  build += " (assertions on)";
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  build += " (sanitizers: timings are not representative)";
#endif
  return build;
}

std::string modeName(const ReportOptions& o) {
  return o.smoke ? "smoke (quick, smallest counts)" : o.quick ? "quick" : "full";
}

std::string formatSeconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", seconds);
  return text;
}

SectionOutcome runSection(const ReportEntry& entry, const ReportContext& base, int index, int count) {
  std::fprintf(stderr, "report [%d/%d] %s\n", index, count, entry.title.c_str());
  std::fflush(stderr);
  SectionOutcome outcome;
  outcome.entry = &entry;
  ProgressBar bar("  " + entry.id);
  ReportContext context = base;
  context.progress = [&bar](double fraction) { bar.update(std::clamp(fraction, 0.0, 1.0)); };
  const auto start = std::chrono::steady_clock::now();
  try {
    outcome.section = entry.run(context);
    if (outcome.section.markdown.rfind("## ", 0) != 0) {
      outcome.section.markdown = "## " + entry.title + "\n\n" + outcome.section.markdown;
    }
  } catch (const std::bad_alloc&) {
    outcome.failed = true;
    outcome.error = "out of memory";
  } catch (const std::exception& e) {  // sdfccd::Error and anything else: the section failed, the report goes on
    outcome.failed = true;
    outcome.error = e.what();
  }
  bar.finish();
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (outcome.failed) {
    std::replace(outcome.error.begin(), outcome.error.end(), '\n', ' ');  // one line (gnuplot quotes its log)
    std::fprintf(stderr, "report: section '%s' failed: %s\n", entry.id.c_str(), outcome.error.c_str());
    outcome.section.ok = false;
    outcome.section.markdown = "## " + entry.title + "\n\n**FAILED**: " + outcome.error + "\n";
  }
  return outcome;
}

int runReport(const ReportOptions& o) {
  // Everything that can be checked before work starts is checked first.
  if (o.threadsGiven && (o.threads < 1 || o.threads > 1024)) {
    throw Error("--threads must be between 1 and 1024 (got " + std::to_string(o.threads) + ")");
  }
  const std::vector<const ReportEntry*> sections = selectSections(o.only);
  if (sections.empty()) throw Error("no report sections are built into this tool");
  const fs::path assets = findAssets(o.assets);
  if (o.out.empty()) throw Error("--out must name a folder");
  const fs::path outDir(o.out);
  OutputFolder outFolder(o.out);  // removed again if the report fails and it was made for it
  // A folder we cannot write into fails now, not after minutes of work.
  checkOutput((outDir / "report.md").string());
  checkOutput((outDir / "report.json").string());

  ReportContext context;
  context.outDir = outDir;
  context.assetsDir = assets;
  context.cacheDir = o.cache;
  context.quick = o.quick || o.smoke;
  context.smoke = o.smoke;
  context.threads = o.threads > 0 ? o.threads : defaultThreadCount();

  const std::string machine = machineDescription();
  const std::string date = utcNow();
  const auto start = std::chrono::steady_clock::now();
  std::vector<SectionOutcome> outcomes;
  for (std::size_t i = 0; i < sections.size(); ++i) {
    outcomes.push_back(runSection(*sections[i], context, static_cast<int>(i) + 1, static_cast<int>(sections.size())));
  }
  const double totalSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::ostringstream md;
  md << "# sdfccd report\n\n"
     << "What accuracy costs in time, hard cases that stay stable, and effects that cost nothing when a scene does "
        "not ask for them; after Xu & Barbic's point-shell / signed-distance-field CCD (the paper's figures are "
        "given beside ours).\n\n"
     << "- Machine: " << machine << " (the paper's: a 2015 Xeon)\n"
     << "- Date: " << date << "\n"
     << "- Mode: " << modeName(o) << "\n"
     << "- Build: " << buildDescription() << "\n"
     << "- Threads: " << context.threads << " (timings are on one core unless a table says otherwise)\n"
     << "- Total time: " << formatSeconds(totalSeconds) << " s\n\n"
     << "| Section | OK | Seconds |\n|---|---|---:|\n";
  int failed = 0, notOk = 0;
  for (const SectionOutcome& s : outcomes) {
    const char* status = s.failed ? "FAILED" : s.section.ok ? "yes" : "no";
    if (s.failed) ++failed;
    if (!s.failed && !s.section.ok) ++notOk;
    md << "| " << s.entry->title << " (`" << s.entry->id << "`) | " << status << " | " << formatSeconds(s.seconds)
       << " |\n";
  }
  md << "\n";
  for (const SectionOutcome& s : outcomes) {
    md << s.section.markdown;
    if (s.section.markdown.empty() || s.section.markdown.back() != '\n') md << '\n';
    md << '\n';
  }

  nlohmann::json json;
  json["machine"] = machine;
  json["date"] = date;
  json["mode"] = o.smoke ? "smoke" : o.quick ? "quick" : "full";
  json["build"] = buildDescription();
  json["threads"] = context.threads;
  json["seconds"] = totalSeconds;
  json["sections"] = nlohmann::json::array();
  for (const SectionOutcome& s : outcomes) {
    nlohmann::json entry = {{"id", s.entry->id},
                            {"title", s.entry->title},
                            {"ok", !s.failed && s.section.ok},
                            {"failed", s.failed},
                            {"seconds", s.seconds}};
    if (s.failed) entry["error"] = s.error;
    json["sections"].push_back(entry);
  }
  writeOutputFile((outDir / "report.json").string(), json.dump(2) + "\n");
  writeOutputFile((outDir / "report.md").string(), md.str());
  outFolder.keep();
  std::printf("wrote %s (%zu sections, %d not ok, %d failed, %.1f s)\n", (outDir / "report.md").string().c_str(),
              outcomes.size(), notOk, failed, totalSeconds);
  if (failed > 0) {
    std::fprintf(stderr, "sdfccd: error: %d report section%s failed (see %s)\n", failed, failed == 1 ? "" : "s",
                 (outDir / "report.md").string().c_str());
    return 1;
  }
  return 0;
}

const CommandRegistrar cmd_reportRegistrar("report", [](CLI::App& app) {
  auto o = std::make_shared<ReportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "report", "Run the experiments and write DIR/report.md (tables beside the paper's figures, PNG plots)");
  cmd->add_flag("--quick", o->quick, "The whole report in a few minutes");
  cmd->add_flag("--smoke", o->smoke, "Tests: quick with the smallest counts")->group("");
  cmd->add_option("--out", o->out, "Output folder (report.md, report.json, CSV and PNG files)")->required();
  cmd->add_option("--only", o->only, "Only these sections, comma-separated ids")->check(nonEmpty());
  cmd->add_option("--assets", o->assets, "The assets folder (default ./assets, else the source tree's)");
  const CLI::Option* cache = addCacheOption(*cmd, o->cache, "Cache of built fields and shells");
  CLI::Option* threads =
      cmd->add_option("--threads", o->threads, "Worker threads for the sections' parallel parts (default: all)");
  return std::function<int()>([o, threads, cache]() {
    o->threadsGiven = threads->count() > 0;
    o->cache = resolveCacheOption(cache, o->cache);
    return runReport(*o);
  });
});

}  // namespace
}  // namespace sdfccd::cli
