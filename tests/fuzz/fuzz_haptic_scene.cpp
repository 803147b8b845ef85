/// @file
/// @brief libFuzzer target: arbitrary bytes into the haptic scene reader (loadHapticScene,
/// sdfccd/haptics/haptic_scene.h), which reads a file: each input is written to a temporary file first.
///
/// @details The contract under test: loadHapticScene either returns a usable scene or throws sdfccd::Error.
/// Any other exception (e.g. a stray nlohmann::json exception), a crash, a leak or undefined behaviour
/// (ASan + UBSan) is a failure. A returned scene must have exactly one static object (grid or plane) or a list of
/// obstacles (each exactly one of grid, plane or shell; shells only with the tool's field), a non-empty shell, a finite
/// positive mass, cell size and session length, and finite inertia.
///
/// Loading does real work sized by the file (a CSG grid, buildSdf, shell sampling), so inputs that ask for
/// a lot of it are skipped before loading (worthLoading): they would only time out. Also skipped: string "path"
/// keys (mesh files from the disk are the mesh loader's business, not this reader's) and the procedural
/// alpha puzzle piece (seconds to generate under the sanitizers), so the mesh-obstacle branch is fuzzed up to
/// its mesh only. The caps are far above what the reader's logic needs to be exercised, and far below what
/// makes one run take seconds. Once the reader range-checks these keys itself, the caps can grow.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/haptics/haptic_scene.h"

namespace {

using Json = nlohmann::json;

// Largest accepted value of the keys that size the loading work.
double workCap(const std::string& key) {
  if (key == "resolution") return 24;
  if (key == "padding" || key == "paddingCells") return 4;
  if (key == "points") return 64;
  if (key == "iterations") return 2;
  if (key == "segments") return 32;
  if (key == "subdivisions") return 2;
  return -1.0;  // not capped
}

bool allNumbersWithin(const Json& j, double bound) {
  if (j.is_number()) return std::fabs(j.get<double>()) <= bound;
  if (j.is_array() || j.is_object()) {
    for (const Json& v : j) {
      if (!allNumbersWithin(v, bound)) return false;
    }
  }
  return true;
}

bool worthLoading(const Json& j) {
  // The procedural alpha puzzle piece takes seconds to generate under the sanitizers, whatever the resolution.
  if (j.is_string()) return j.get<std::string>() != "alpha-puzzle-piece";
  if (j.is_array()) {
    for (const Json& v : j) {
      if (!worthLoading(v)) return false;
    }
    return true;
  }
  if (!j.is_object()) return true;
  // Defaults are sized for real sessions (1,000 shell points, 64-cell meshes): require small explicit values.
  if (j.contains("shape") && (!j.contains("points") || !j.contains("iterations"))) return false;
  if (j.contains("procedural") && !j.contains("resolution")) return false;
  // A CSG grid: spacing >= 0.02 over solids within +-1 is at most ~110 nodes per axis.
  if (j.contains("spacing") && j.at("spacing").is_number() && j.at("spacing").get<double>() < 0.02) return false;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it.key() == "path" && it.value().is_string()) return false;  // a mesh file (an obstacle's keyframes are fuzzed)
    if ((it.key() == "solids" || it.key() == "holes") && !allNumbersWithin(it.value(), 1.0)) return false;
    const double cap = workCap(it.key());
    if (cap >= 0.0 && it.value().is_number() && !(it.value().get<double>() <= cap)) return false;
    if (!worthLoading(it.value())) return false;
  }
  return true;
}

bool usableObstacles(const sdfccd::haptics::HapticScene& s) {
  if (s.grid || s.plane) return false;  // "obstacles" replaces the one static object
  for (const sdfccd::haptics::HapticObstacle& o : s.obstacles) {
    const int kinds = (o.grid != nullptr) + o.plane.has_value() + (o.shell != nullptr);
    if (kinds != 1 || (o.shell && (!s.toolField || o.shell->pointCount() == 0))) return false;
    if (!o.path.poseAt(0.0).matrix().allFinite()) return false;
  }
  return true;
}

bool usable(const sdfccd::haptics::HapticScene& s) {
  if (s.obstacles.empty() ? (s.grid != nullptr) == s.plane.has_value() : !usableObstacles(s)) return false;
  if (!s.tree || s.tree->pointCount() == 0) return false;
  return std::isfinite(s.mass) && s.mass > 0.0 && std::isfinite(s.cellSize) && s.cellSize > 0.0 &&
         std::isfinite(s.seconds) && s.seconds > 0.0 && s.inertiaDiagonal.allFinite();
}

// The file each input is written to, removed when the fuzzer exits.
struct ScratchFile {
  std::string path = "/tmp/sdfccd-fuzz-haptic-" + std::to_string(::getpid()) + ".json";
  ~ScratchFile() { std::remove(path.c_str()); }
};

const std::string& scratchPath() {
  static const ScratchFile file;
  return file.path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const Json parsed = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!parsed.is_discarded() && !worthLoading(parsed)) return 0;
  {
    std::ofstream out(scratchPath(), std::ios::binary | std::ios::trunc);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!out) std::abort();  // the harness itself failed
  }
  sdfccd::haptics::HapticScene scene;
  try {
    scene = sdfccd::haptics::loadHapticScene(scratchPath());
  } catch (const sdfccd::Error&) {
    return 0;  // rejected with the one exception type: fine
  }
  if (!usable(scene)) std::abort();  // accepted an unusable scene
  return 0;
}
