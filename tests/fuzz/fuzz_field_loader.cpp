/// @file
/// @brief libFuzzer target: arbitrary bytes into the SDF loader (native binary and SDFGen text, sdf_file.h).
///
/// @details The contract under test: parseSdf either returns a valid grid or throws sdfccd::Error. Any other
/// exception, a crash, a leak or undefined behaviour (ASan + UBSan) is a failure. A returned grid must be
/// usable: at least 2 nodes per axis, finite origin and spacing, one finite value per node, and its
/// interpolation at the box's centre finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/field/sdf_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  sdfccd::SdfGrid grid;
  try {
    grid = sdfccd::parseSdf(bytes, "fuzz");
  } catch (const sdfccd::Error&) {
    return 0;  // rejected with the one exception type: fine
  }
  const sdfccd::Vec3i nodes = grid.nodeCounts();
  const std::size_t count =
      static_cast<std::size_t>(nodes.x()) * static_cast<std::size_t>(nodes.y()) * static_cast<std::size_t>(nodes.z());
  bool valid = nodes.minCoeff() >= 2 && grid.origin().allFinite() && std::isfinite(grid.spacing()) &&
               grid.spacing() > 0.0 && grid.values().size() == count;
  for (const float v : grid.values()) valid = valid && std::isfinite(v);
  if (valid) valid = std::isfinite(grid.interpolate(grid.box().center()));
  if (!valid) std::abort();  // accepted an invalid grid
  return 0;
}
