/// @file
/// @brief The sdfccd command-line tool: builds fields, runs queries, simulations, benchmarks and reports.
#include <algorithm>
#include <iostream>
#include <map>
#include <string>

#include "cli/command_registry.h"
#include "sdfccd/error.h"
#include "sdfccd/output_file.h"

namespace {

/// An error message as one terminal line: names from input files (a scene's body names, paths) may hold
/// newlines or escape sequences; every control character is shown as '?'.
std::string oneLine(const char* what) {
  std::string line = what;
  for (char& c : line) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  }
  return line;
}

}  // namespace

int main(int argc, char** argv) {
  // An interrupted command leaves no temporary output file or empty run folder behind.
  sdfccd::installTempFileCleanupHandlers();
  CLI::App app{"sdfccd: continuous collision detection between point shells and signed distance fields"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "sdfccd 0.1.0");
  auto& registry = sdfccd::cli::commandRegistry();
  std::sort(registry.begin(), registry.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  std::map<CLI::App*, std::function<int()>> runners;
  for (auto& entry : registry) {
    auto run = entry.setup(app);
    runners[app.get_subcommand(entry.name)] = std::move(run);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "sdfccd: error: " << oneLine(e.what()) << "\n";
    return e.get_exit_code() != 0 ? e.get_exit_code() : 2;
  }
  try {
    for (auto* sub : app.get_subcommands()) return runners.at(sub)();
  } catch (const sdfccd::Error& e) {
    std::cerr << "sdfccd: error: " << oneLine(e.what()) << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "sdfccd: error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "sdfccd: error: " << oneLine(e.what()) << "\n";
    return 1;
  }
  return 2;
}
