/// @file
/// @brief `sdfccd info FIELD`: dimensions, box, spacing, value range and memory of a field file.
#include <cstdio>
#include <memory>

#include "cli/command_registry.h"
#include "sdfccd/field/sdf_file.h"

namespace sdfccd::cli {
namespace {

int runInfo(const std::string& path) {
  const SdfGrid grid = loadSdf(path);
  const Box3 box = grid.box();
  std::size_t inside = 0;
  for (float v : grid.values()) inside += v < 0.0f ? 1 : 0;
  std::printf("file:        %s\n", path.c_str());
  std::printf("dimensions:  %d x %d x %d nodes (%d x %d x %d cells)\n", grid.nodeCounts().x(), grid.nodeCounts().y(),
              grid.nodeCounts().z(), grid.cellCounts().x(), grid.cellCounts().y(), grid.cellCounts().z());
  std::printf("box:         [%.9g %.9g %.9g] - [%.9g %.9g %.9g]\n", box.min().x(), box.min().y(), box.min().z(),
              box.max().x(), box.max().y(), box.max().z());
  std::printf("spacing:     %.9g\n", grid.spacing());
  std::printf("values:      %.9g .. %.9g (%zu of %zu nodes inside)\n", grid.minValue(), grid.maxValue(), inside,
              grid.values().size());
  std::printf("memory:      %.2f MiB\n", grid.memoryBytes() / (1024.0 * 1024.0));
  return 0;
}

const CommandRegistrar cmd_infoRegistrar("info", [](CLI::App& app) {
  auto path = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("info", "Describe a signed distance field file (native or SDFGen)");
  cmd->add_option("field", *path, "Field file")->required();
  return std::function<int()>([path]() { return runInfo(*path); });
});

}  // namespace
}  // namespace sdfccd::cli
