/// @file
/// @brief TrajectoryPlayer: replays a recorded trajectory as a haptic device (see trajectory_player.h).
#include "sdfccd/haptics/trajectory_player.h"

#include <algorithm>
#include <cmath>

#include "sdfccd/error.h"

namespace sdfccd::haptics {

TrajectoryPlayer::TrajectoryPlayer(UserScript recording, double rateHz)
    : m_recording(std::move(recording)), m_rateHz(rateHz) {
  if (!(std::isfinite(rateHz) && rateHz > 0.0 && rateHz <= 1e6))
    throw Error("trajectory player: rate must be in (0, 1e6] Hz");
  if (m_recording.keys().empty()) throw Error("trajectory player: the recording is empty");
  const double span = m_recording.keys().back().time - m_recording.keys().front().time;
  // Ticks at t0 + n T for n = 0 .. floor(span / T), the last one at (or just before) the last row.
  m_tickCount = static_cast<std::int64_t>(std::floor(span * rateHz + 1e-9)) + 1;
  enterTick(0);
}

TrajectoryPlayer TrajectoryPlayer::fromCsv(const std::string& path, double rateHz) {
  return TrajectoryPlayer(UserScript::loadCsv(path), rateHz);
}

Rigid TrajectoryPlayer::poseAtTick(std::int64_t n) const {
  const std::vector<PoseKeyframe>& keys = m_recording.keys();
  const double period = 1.0 / m_rateHz;
  const double t = keys.front().time + static_cast<double>(n) * period;
  // The row at this tick's time, if there is one: replayed as recorded (no interpolation round-off).
  const auto row = std::lower_bound(keys.begin(), keys.end(), t - 1e-9 * period,
                                    [](const PoseKeyframe& k, double time) { return k.time < time; });
  if (row != keys.end() && std::abs(row->time - t) <= 1e-9 * period) return row->worldFromTarget;
  return m_recording.targetAt(t);
}

void TrajectoryPlayer::enterTick(std::int64_t n) {
  m_state.tick = n;
  m_state.time = static_cast<double>(n) / m_rateHz;
  m_state.body.worldFromBody = poseAtTick(n);
  m_state.worldFromTarget = m_state.body.worldFromBody;
  Vec6 twist = Vec6::Zero();
  if (n + 1 < m_tickCount) twist = poseDifference(m_state.body.worldFromBody, poseAtTick(n + 1)) * m_rateHz;
  m_state.body.linearVelocity = twist.head<3>();
  m_state.body.angularVelocity = twist.tail<3>();
}

void TrajectoryPlayer::write(const Vec6& wrench) {
  if (ticksLeft() <= 0) throw Error("trajectory player: written past the end of the recording");
  const Vec6 w = wrench.allFinite() ? wrench : Vec6::Zero();
  m_wrenches.push_back(w);
  m_state.renderedWrench = w;
  enterTick(m_state.tick + 1);
}

}  // namespace sdfccd::haptics
