/// @file
/// @brief The sdfccd command-line tool: builds fields, runs queries, simulations, benchmarks and reports.
#include <algorithm>
#include <iostream>
#include <map>

#include "cli/command_registry.h"
#include "sdfccd/error.h"

int main(int argc, char** argv) {
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
    std::cerr << "sdfccd: error: " << e.what() << "\n";
    return e.get_exit_code() != 0 ? e.get_exit_code() : 2;
  }
  try {
    for (auto* sub : app.get_subcommands()) return runners.at(sub)();
  } catch (const sdfccd::Error& e) {
    std::cerr << "sdfccd: error: " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "sdfccd: error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "sdfccd: error: " << e.what() << "\n";
    return 1;
  }
  return 2;
}
