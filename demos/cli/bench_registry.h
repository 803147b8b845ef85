/// @file
/// @brief Benchmarks register themselves here; `sdfccd bench <name>` runs one (see cmd_bench.cpp).
///
/// @details Same pattern as command_registry.h: each demos/bench/bench_<name>.cpp (or cli file) defines a
/// static BenchRegistrar whose setup adds options to the `bench <name>` subcommand and returns the runner.
/// Benchmarks print the paper's figure beside ours, state the machine, and write CSV.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace sdfccd::cli {

using BenchSetup = std::function<std::function<int()>(CLI::App& benchSubcommand)>;

struct BenchEntry {
  std::string name;
  std::string description;
  BenchSetup setup;
};

inline std::vector<BenchEntry>& benchRegistry() {
  static std::vector<BenchEntry> registry;
  return registry;
}

struct BenchRegistrar {
  BenchRegistrar(std::string name, std::string description, BenchSetup setup) {
    benchRegistry().push_back({std::move(name), std::move(description), std::move(setup)});
  }
};

/// One line naming the machine (CPU model, cores) for benchmark headers.
std::string machineDescription();

}  // namespace sdfccd::cli
