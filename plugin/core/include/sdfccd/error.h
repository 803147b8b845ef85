/// @file
/// @brief The one exception type of sdfccd: a clear, one-line message for bad input.
///
/// @details Every loader and builder reports bad input (missing, corrupt or truncated files, NaN/inf,
/// absurd parameters) by throwing sdfccd::Error with a single line that names the offending file, line or
/// parameter. Tools catch it at the top, print it on stderr and exit non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace sdfccd {

/// Bad input or an impossible request. what() is one line, no trailing newline.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace sdfccd
