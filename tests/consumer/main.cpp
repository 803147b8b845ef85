// Builds a 2x2x2-node field phi(x,y,z) = x + 2y + 3z - 1 and checks trilinear interpolation at one point; parses
// a one-body scene with the model layer.
#include <sdfccd/field/sdf_grid.h>
#include <sdfccd/model/scene.h>

#include <cmath>
#include <cstdio>

int main() {
  std::vector<float> values;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) values.push_back(static_cast<float>(i + 2 * j + 3 * k - 1));
  sdfccd::SdfGrid grid({2, 2, 2}, sdfccd::Vec3::Zero(), 1.0, std::move(values));
  const double phi = grid.interpolate(sdfccd::Vec3(0.25, 0.5, 0.75));
  const double expected = 0.25 + 1.0 + 2.25 - 1.0;
  if (std::abs(phi - expected) > 1e-12) {
    std::printf("consumer: got %.17g, expected %.17g\n", phi, expected);
    return 1;
  }
  const sdfccd::Scene scene = sdfccd::parseScene(
      R"({"bodies": [{"primitive": {"type": "sphere", "radius": 0.1}, "mass": 2.0}]})", "consumer", ".");
  if (scene.bodies.size() != 1 || scene.bodies[0].mass != 2.0) {
    std::printf("consumer: the scene was not read\n");
    return 1;
  }
  std::printf("consumer: ok\n");
  return 0;
}
