/// @file
/// @brief The sdfccd tool's subcommands register themselves here, one file per subcommand.
///
/// @details Each cli/cmd_*.cpp defines a static CommandRegistrar that adds its CLI11 subcommand; main()
/// parses and runs the chosen one. Errors: a subcommand throws sdfccd::Error (or CLI11's errors) and main()
/// prints one line on stderr and exits non-zero.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace sdfccd::cli {

/// Adds a subcommand to `app` and returns the function that runs it after parsing (returns the exit code).
using CommandSetup = std::function<std::function<int()>(CLI::App& app)>;

struct CommandEntry {
  std::string name;
  CommandSetup setup;
};

inline std::vector<CommandEntry>& commandRegistry() {
  static std::vector<CommandEntry> registry;
  return registry;
}

struct CommandRegistrar {
  CommandRegistrar(std::string name, CommandSetup setup) {
    commandRegistry().push_back({std::move(name), std::move(setup)});
  }
};

}  // namespace sdfccd::cli
