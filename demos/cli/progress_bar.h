/// @file
/// @brief ProgressBar: a text progress bar on stderr for long work (shown only after about a second).
///
/// @details Usage: `ProgressBar bar("building SDF"); settings.progress = bar.callback(); ... bar.finish();`
/// The bar stays silent for work shorter than `delaySeconds` (default 1 s), then redraws itself on one line
/// of stderr with '\r' at most ~10 times a second. update() is thread-safe (a mutex; calls are cheap when
/// nothing is redrawn). finish() (also called by the destructor) ends the line with a newline if the bar was
/// ever shown, so the next output starts on a fresh line. When stderr is not a terminal (a log file, CI) the
/// bar prints plain lines instead of redrawing, one per 10% step after the delay, so long work shows progress
/// in logs too while short work prints nothing.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>

namespace sdfccd::cli {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label, double delaySeconds = 1.0)
      : m_label(std::move(label)),
        m_delaySeconds(delaySeconds),
        m_terminal(::isatty(STDERR_FILENO) != 0),
        m_start(Clock::now()),
        m_lastDraw(m_start) {}
  ~ProgressBar() { finish(); }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Reports the fraction done in [0, 1]. Safe to call from any thread.
  void update(double fractionDone) {
    std::lock_guard<std::mutex> lock(m_mutex);
    if (m_finished) return;
    const Clock::time_point now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - m_start).count();
    if (elapsed < m_delaySeconds) return;
    if (!m_terminal) {
      const int step = static_cast<int>(std::clamp(fractionDone, 0.0, 1.0) * 10.0);
      if (step <= m_lastStep || step >= 10) return;  // the end is printed by finish()
      m_lastStep = step;
      m_shown = true;
      std::fprintf(stderr, "%s: %d%% (%.1f s)\n", m_label.c_str(), step * 10, elapsed);
      std::fflush(stderr);
      return;
    }
    if (m_shown && std::chrono::duration<double>(now - m_lastDraw).count() < 0.1 && fractionDone < 1.0) return;
    m_lastDraw = now;
    m_shown = true;
    draw(std::clamp(fractionDone, 0.0, 1.0), elapsed);
  }

  /// A callback suitable for sdfccd::ProgressCallback (the bar must outlive it).
  std::function<void(double)> callback() {
    return [this](double fractionDone) { update(fractionDone); };
  }

  /// Ends the bar's line (only if it was shown). Idempotent.
  void finish() {
    std::lock_guard<std::mutex> lock(m_mutex);
    if (m_finished) return;
    m_finished = true;
    if (m_shown) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - m_start).count();
      if (!m_terminal) {
        std::fprintf(stderr, "%s: done (%.1f s)\n", m_label.c_str(), elapsed);
        std::fflush(stderr);
        return;
      }
      draw(1.0, elapsed);
      std::fputc('\n', stderr);
      std::fflush(stderr);
    }
  }

 private:
  using Clock = std::chrono::steady_clock;

  void draw(double fraction, double elapsed) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth + 0.5);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.append(static_cast<std::size_t>(kWidth - filled), '-');
    std::fprintf(stderr, "\r%s [%s] %3d%% %6.1f s", m_label.c_str(), bar.c_str(), static_cast<int>(fraction * 100.0),
                 elapsed);
    std::fflush(stderr);
  }

  std::string m_label;
  double m_delaySeconds;
  bool m_terminal;
  int m_lastStep = 0;
  Clock::time_point m_start;
  Clock::time_point m_lastDraw;
  bool m_shown = false;
  bool m_finished = false;
  std::mutex m_mutex;
};

}  // namespace sdfccd::cli
