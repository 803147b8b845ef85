/// @file
/// @brief `sdfccd convert IN OUT [--format native|sdfgen]`: converts between the native and SDFGen formats.
#include <cstdio>
#include <memory>

#include "cli/command_registry.h"
#include "sdfccd/field/sdf_file.h"
#include "sdfccd/output_file.h"

namespace sdfccd::cli {
namespace {

struct ConvertOptions {
  std::string input;
  std::string output;
  std::string format;
};

int runConvert(const ConvertOptions& o) {
  const SdfFileFormat format = o.format.empty() ? sdfFileFormatForPath(o.output) : parseSdfFileFormat(o.format);
  checkOutput(o.output, {o.input});  // `convert a.sdf a.sdf` is refused before reading
  const SdfGrid grid = loadSdf(o.input);
  saveSdf(o.output, grid, format);
  std::fprintf(o.output == "-" ? stderr : stdout, "wrote %s (%s, %d x %d x %d nodes)\n", o.output.c_str(),
               toString(format), grid.nodeCounts().x(), grid.nodeCounts().y(), grid.nodeCounts().z());
  return 0;
}

const CommandRegistrar cmd_convertRegistrar("convert", [](CLI::App& app) {
  auto o = std::make_shared<ConvertOptions>();
  CLI::App* cmd = app.add_subcommand("convert", "Convert a field between the native and SDFGen formats");
  cmd->add_option("input", o->input, "Input field (format detected by content)")->required();
  cmd->add_option("output", o->output, "Output field (- for stdout)")->required();
  cmd->add_option("--format", o->format, "native or sdfgen (default: sdfgen for .sdfgen, else native)");
  return std::function<int()>([o]() { return runConvert(*o); });
});

}  // namespace
}  // namespace sdfccd::cli
