// Small scenes for the Bullet suite: fields of a few dozen cells and a few hundred points keep it fast.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/model/body_model.h"
#include "sdfccd/model/scene.h"

namespace sdfccd::test {

/// A scene from JSON text (paths relative to the assets folder).
inline Scene sceneFromText(const std::string& text) {
  return parseScene(text, "test", SDFCCD_ASSETS_DIR);
}

/// Model settings of the suites' small bodies: `resolution` field cells on the mesh's longest side, `points`
/// shell points, `threads` build threads (0: all cores).
inline BodyModelSettings smallModelSettings(int resolution, int points, int threads = 0) {
  BodyModelSettings s;
  s.resolution = resolution;
  s.points = points;
  s.threads = threads;
  return s;
}

/// The bunny of assets/meshes/bunny.off scaled to 0.2 m, 48 field cells on its longest side, `points` shell points.
inline std::shared_ptr<const BodyModel> buildTestBunny(int points) {
  BodyModelSettings s = smallModelSettings(48, points);
  s.scale = 0.2;
  return BodyModel::buildFromMeshFile(std::string(SDFCCD_ASSETS_DIR) + "/meshes/bunny.off", s);
}

/// Runs `action`, which must throw an sdfccd::Error whose message is one line containing `expected`
/// (`context` is added to the failure when it does not throw).
template <class Action>
void expectOneLineError(Action&& action, const std::string& expected, const std::string& context = "") {
  try {
    action();
    ADD_FAILURE() << "accepted: " << expected << context;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(expected), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace sdfccd::test
