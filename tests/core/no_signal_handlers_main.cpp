/// @file
/// @brief A program that links sdfccd::core alone and saves a field (an atomic write: temporary file, then
/// rename) finds SIGINT, SIGTERM, SIGHUP and SIGPIPE as it left them: the library installs no signal handler.
/// A plain main (no test framework), so that nothing but the core can have touched the dispositions.
/// Exit status 0 on success; a message and 1 otherwise.
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "sdfccd/field/sdf_file.h"
#include "sdfccd/field/sdf_grid.h"
#include "sdfccd/output_file.h"
#include "sdfccd/output_folder.h"

namespace {

constexpr std::pair<int, const char*> kSignals[] = {
    {SIGINT, "SIGINT"}, {SIGTERM, "SIGTERM"}, {SIGHUP, "SIGHUP"}, {SIGPIPE, "SIGPIPE"}};

/// Counts the signals whose action is not SIG_DFL, naming each.
int countChangedSignals(const char* when) {
  int changed = 0;
  for (const auto& [number, name] : kSignals) {
    struct sigaction current {};
    if (::sigaction(number, nullptr, &current) != 0) {
      std::fprintf(stderr, "%s: sigaction(%s) failed\n", when, name);
      ++changed;
      continue;
    }
    if ((current.sa_flags & SA_SIGINFO) != 0 || current.sa_handler != SIG_DFL) {
      std::fprintf(stderr, "%s: %s has a handler or is ignored\n", when, name);
      ++changed;
    }
  }
  return changed;
}

}  // namespace

int main() {
  // The dispositions start at the default whatever the parent left ignored (an ignored signal is inherited).
  for (const auto& [number, name] : kSignals) ::signal(number, SIG_DFL);

  char pattern[] = "/tmp/sdfccd-no-signal-handlers-XXXXXX";
  if (::mkdtemp(pattern) == nullptr) {
    std::perror("mkdtemp");
    return 1;
  }
  const std::string folder = pattern;
  int failures = 0;
  try {
    const sdfccd::OutputFolder run(folder + "/run");  // a created folder is registered for cleanup too
    std::vector<float> values(4 * 4 * 4);
    for (std::size_t n = 0; n < values.size(); ++n) values[n] = static_cast<float>(n) * 0.01f - 0.3f;
    const sdfccd::SdfGrid grid(sdfccd::Vec3i(4, 4, 4), sdfccd::Vec3::Zero(), 0.1, std::move(values));
    sdfccd::saveSdf(folder + "/run/field.sdf", grid);
    sdfccd::writeOutputFile(folder + "/run/notes.txt", "saved\n");
    if (!std::filesystem::is_regular_file(folder + "/run/field.sdf")) {
      std::fprintf(stderr, "the field was not saved\n");
      ++failures;
    }
    failures += countChangedSignals("after saving a field");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    ++failures;
  }
  std::error_code ignored;
  std::filesystem::remove_all(folder, ignored);
  if (failures == 0) std::printf("no signal handler installed by sdfccd::core\n");
  return failures == 0 ? 0 : 1;
}
