/// @file
/// @brief UserScript: the scripted user of the emulated device, a target pose over time.
///
/// @details The emulated hand pulls the device towards a target pose through a spring-damper
/// (device_emulator.h). The target comes from keyframes (positions interpolated linearly, orientations by
/// slerp; held constant before the first and after the last key) or from a recorded trajectory in CSV with
/// the header "t,x,y,z,qw,qx,qy,qz" (seconds, model units, unit quaternion; normalized on load).
#pragma once

#include <string>
#include <vector>

#include "sdfccd/math_types.h"

namespace sdfccd::haptics {

/// One key of the target trajectory.
struct PoseKeyframe {
  double time = 0.0;                          ///< s, strictly increasing along the script
  Rigid worldFromTarget = Rigid::Identity();  ///< the pose the user aims the device at
};

class UserScript {
 public:
  UserScript() = default;
  /// Throws sdfccd::Error on no keys, non-increasing or non-finite times, or non-finite poses.
  explicit UserScript(std::vector<PoseKeyframe> keys);
  /// Reads a recorded trajectory (see the file comment). Throws sdfccd::Error naming the file and line on
  /// a missing file, a wrong header, a short row, a non-number, NaN/inf, a zero quaternion or times that do
  /// not increase.
  static UserScript loadCsv(const std::string& path);

  /// The target at `time` (s), clamped to the first and last keys.
  Rigid targetAt(double time) const;
  double duration() const { return m_keys.empty() ? 0.0 : m_keys.back().time; }  ///< s, time of the last key
  const std::vector<PoseKeyframe>& keys() const { return m_keys; }
  /// The fastest the target moves (model units / s): the largest distance between consecutive keys over their time.
  double peakSpeed() const;

 private:
  std::vector<PoseKeyframe> m_keys;
};

}  // namespace sdfccd::haptics
