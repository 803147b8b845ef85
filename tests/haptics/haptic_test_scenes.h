/// @file
/// @brief Where the haptics suites find the shipped haptic scenes (assets/scenes/haptics).
#pragma once

#include <string>

namespace sdfccd::haptics::test {

/// The path of the shipped haptic scene `name` (a file name under assets/scenes/haptics).
inline std::string scenePath(const std::string& name) {
  return std::string(SDFCCD_ASSETS_DIR) + "/scenes/haptics/" + name;
}

}  // namespace sdfccd::haptics::test
