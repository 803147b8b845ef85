/// @file
/// @brief External programs the tool drives (gnuplot for plots, ffmpeg for videos): finding and running them.
///
/// @details Programs are run with fork/execvp and an argument vector (no shell, so paths need no quoting);
/// their standard output and error go to a log file so the tool's own output stays clean, and the log's last
/// lines are quoted in the error when the program fails.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace sdfccd::cli {

/// The full path of `name` found on PATH, or nothing.
std::optional<std::string> findProgram(const std::string& name);

/// Result of runProgram.
struct ProgramRun {
  int exitCode = -1;    ///< the program's exit status; -1 if it could not be started or was killed
  std::string logTail;  ///< the last lines it printed (stdout and stderr)
};

/// Runs `arguments[0]` (found on PATH) with the rest as its arguments, waiting for it to end; its output goes to
/// `logPath` (overwritten). Never throws for a failing program: the caller decides what a failure means.
ProgramRun runProgram(const std::vector<std::string>& arguments, const std::string& logPath);

}  // namespace sdfccd::cli
