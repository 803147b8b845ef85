/// @file
/// @brief libFuzzer target: arbitrary bytes into the scene JSON parser (parseScene, sdfccd/model/scene.h).
///
/// @details The contract under test: parseScene either returns a valid scene or throws sdfccd::Error. Any
/// other exception (e.g. a stray nlohmann::json exception), a crash, a leak or undefined behaviour (ASan +
/// UBSan) is a failure. A returned scene must hold what SceneWorld relies on: a finite positive timestep,
/// at least one frame and one body, finite vectors, unit quaternions, positive finite masses for dynamic
/// bodies and exactly one of mesh and primitive per body. Relative paths resolve against the current folder.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/model/scene.h"

namespace {

bool validBody(const sdfccd::SceneBody& b) {
  if (b.mesh.empty() == !b.primitive.has_value()) return false;
  if (!b.position.allFinite() || !b.velocity.allFinite() || !b.angularVelocity.allFinite()) return false;
  if (!b.orientation.coeffs().allFinite() || std::abs(b.orientation.norm() - 1.0) > 1e-6) return false;
  if (!std::isfinite(b.scale) || !(b.scale > 0.0)) return false;
  if (!b.isStatic && (!std::isfinite(b.mass) || !(b.mass > 0.0))) return false;
  return b.resolution >= 1 && b.padding >= 0 && b.points >= 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  sdfccd::Scene scene;
  try {
    scene = sdfccd::parseScene(text, "fuzz", ".");
  } catch (const sdfccd::Error&) {
    return 0;  // rejected with the one exception type: fine
  }
  bool valid = std::isfinite(scene.timestep) && scene.timestep > 0.0 && scene.frames >= 1 && !scene.bodies.empty() &&
               scene.gravity.allFinite() && std::isfinite(scene.groundHeight) &&
               std::isfinite(scene.contact.stiffness) && scene.contact.stiffness > 0.0 &&
               std::isfinite(scene.contact.damping) && scene.contact.damping >= 0.0 && scene.contact.subintervals >= 1;
  for (const sdfccd::SceneBody& b : scene.bodies) valid = valid && validBody(b);
  if (!valid) std::abort();  // accepted an invalid scene
  return 0;
}
