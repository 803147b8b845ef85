/// @file
/// @brief TrajectoryPlayer: a HapticDevice that replays a recorded trajectory (a lab's logged hand motion) and
/// records the wrenches the renderer writes to it.
///
/// @details The recording is the CSV of user_script.h: header "t,x,y,z,qw,qx,qy,qz", one row per sample (seconds,
/// model units, unit quaternion, normalized on load), times strictly increasing. Tick n of the player is at time
/// t0 + n * period (t0: the first row's time). Its pose is the recorded row when the row's time is the tick's time
/// (up to 1e-9 of a period), so a recording sampled at the device rate replays row by row, bit for bit; between
/// rows it is interpolated (positions linearly, orientations by slerp). Its twist is the displacement to the next
/// tick's pose over one period (the symplectic convention of the emulator: x_{n+1} = x_n + T v_n), zero at the last
/// tick. The player ends after the tick at the last row's time (ticksLeft() = 0). The written wrenches do not move
/// it (a recording is kinematic); they are kept, one per tick, in wrenches().
#pragma once

#include <string>
#include <vector>

#include "sdfccd/haptics/haptic_device.h"
#include "sdfccd/haptics/user_script.h"

namespace sdfccd::haptics {

class TrajectoryPlayer : public HapticDevice {
 public:
  /// Throws sdfccd::Error on a rate outside (0, 1e6] Hz.
  TrajectoryPlayer(UserScript recording, double rateHz);
  /// Loads the CSV (errors as UserScript::loadCsv: one line naming the file and line).
  static TrajectoryPlayer fromCsv(const std::string& path, double rateHz);

  double rateHz() const override { return m_rateHz; }
  const DeviceState& state() const override { return m_state; }
  void write(const Vec6& wrench) override;
  std::int64_t ticksLeft() const override { return m_tickCount - m_state.tick; }

  std::int64_t tickCount() const { return m_tickCount; }  ///< ticks in the recording
  /// The pose of tick n (see the file comment).
  Rigid poseAtTick(std::int64_t n) const;
  const std::vector<Vec6>& wrenches() const { return m_wrenches; }  ///< one per written tick

 private:
  void enterTick(std::int64_t n);

  UserScript m_recording;
  double m_rateHz;
  std::int64_t m_tickCount = 0;
  DeviceState m_state;
  std::vector<Vec6> m_wrenches;
};

}  // namespace sdfccd::haptics
