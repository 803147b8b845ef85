/// @file
/// @brief libFuzzer target: arbitrary bytes into the point shell reader (ascii PLY and CSV, point_shell.h).
///
/// @details The contract under test: parseShell either returns a valid shell or throws sdfccd::Error. Any
/// other exception, a crash, a leak or undefined behaviour (ASan + UBSan) is a failure. Every input is read
/// as both formats. A returned shell must be non-empty and pass PointShell::validate() (finite points, unit
/// normals, equal counts).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/shell/point_shell.h"

namespace {

void readAs(const std::string& bytes, const char* name) {
  sdfccd::PointShell shell;
  try {
    shell = sdfccd::parseShell(bytes, name);
  } catch (const sdfccd::Error&) {
    return;  // rejected with the one exception type: fine
  }
  if (shell.empty()) std::abort();  // accepted an empty shell
  try {
    shell.validate();
  } catch (const sdfccd::Error&) {
    std::abort();  // accepted an invalid shell
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  readAs(bytes, "fuzz.ply");
  readAs(bytes, "fuzz.csv");
  return 0;
}
