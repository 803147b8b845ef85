// Small scenes for the Bullet suite: fields of a few dozen cells and a few hundred points keep it fast.
#pragma once

#include <string>

#include "sdfccd/bullet/scene.h"

namespace sdfccd::test {

/// A scene from JSON text (paths relative to the assets folder).
inline Scene sceneFromText(const std::string& text) {
  return parseScene(text, "test", SDFCCD_ASSETS_DIR);
}

}  // namespace sdfccd::test
