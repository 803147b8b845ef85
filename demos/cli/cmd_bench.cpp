/// @file
/// @brief `sdfccd bench <name> [options]`: runs one registered benchmark.
#include <algorithm>
#include <fstream>
#include <map>
#include <memory>
#include <thread>

#include "cli/bench_registry.h"
#include "cli/command_registry.h"

namespace sdfccd::cli {

std::string machineDescription() {
  std::string model = "unknown CPU";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) model = line.substr(colon + 2);
      break;
    }
  }
  return model + ", " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads";
}

namespace {

const CommandRegistrar cmd_benchRegistrar("bench", [](CLI::App& app) {
  CLI::App* bench = app.add_subcommand("bench", "Run a benchmark (prints the paper's figures beside ours)");
  bench->require_subcommand(1);
  auto runners = std::make_shared<std::map<CLI::App*, std::function<int()>>>();
  auto& registry = benchRegistry();
  std::sort(registry.begin(), registry.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  for (auto& entry : registry) {
    CLI::App* sub = bench->add_subcommand(entry.name, entry.description);
    (*runners)[sub] = entry.setup(*sub);
  }
  return std::function<int()>([bench, runners]() {
    for (auto* sub : bench->get_subcommands()) return runners->at(sub)();
    return 2;
  });
});

}  // namespace
}  // namespace sdfccd::cli
