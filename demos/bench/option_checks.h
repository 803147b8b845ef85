/// @file
/// @brief Validators of `sdfccd bench ...` and `sdfccd report` options: a zero or negative count, an empty list or
/// an unknown name is a one-line error naming the option (CLI11 prefixes the option's name), exit code non-zero,
/// never a silent fall back to the default (or to an empty CSV).
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <string>

namespace sdfccd::cli {

/// An integer in [lo, hi].
inline CLI::Validator countIn(long long lo, long long hi) {
  return CLI::Range(lo, hi);
}

/// A finite number in (0, hi] (NaN fails too: CLI::PositiveNumber lets it through).
inline CLI::Validator positiveUpTo(double hi) {
  return CLI::Validator(
      [hi](std::string& text) -> std::string {
        double v = 0.0;
        try {
          std::size_t used = 0;
          v = std::stod(text, &used);
          if (used != text.size()) return "'" + text + "' is not a number";
        } catch (const std::exception&) {
          return "'" + text + "' is not a number";
        }
        if (!(v > 0.0 && v <= hi)) return "must be in (0, " + CLI::detail::to_string(hi) + "] (got " + text + ")";
        return {};
      },
      "POSITIVE");
}

/// A non-empty value: an empty list or name is a mistake, not "the default".
inline CLI::Validator nonEmpty() {
  return CLI::Validator([](std::string& text) -> std::string { return text.empty() ? "must not be empty" : ""; },
                        "NONEMPTY");
}

}  // namespace sdfccd::cli
