/// @file
/// @brief libFuzzer target: arbitrary bytes into the segment file parser of `sdfccd query` (parseSegments,
/// sdfccd/ccd/segment_file.h).
///
/// @details The contract under test: parseSegments either returns segments or throws sdfccd::Error whose
/// message is one line starting with the file's name. Any other exception, a crash, a leak or undefined
/// behaviour (ASan + UBSan) is a failure. Returned segments must hold finite endpoints and sigma, with line
/// numbers increasing from 1 and within the input's line count.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "sdfccd/ccd/segment_file.h"
#include "sdfccd/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::istringstream in(text);
  std::vector<sdfccd::SegmentRecord> segments;
  try {
    segments = sdfccd::parseSegments(in, "fuzz", 0.125);
  } catch (const sdfccd::Error& e) {
    const std::string message = e.what();
    // One line (a NUL byte ends a value's quote early but never adds a newline), naming the input.
    if (message.rfind("fuzz", 0) != 0 || message.find('\n') != std::string::npos) std::abort();
    return 0;
  }
  std::size_t lines = 1;
  for (const char c : text) lines += c == '\n' ? 1 : 0;
  int previous = 0;
  for (const sdfccd::SegmentRecord& s : segments) {
    if (!s.p0.allFinite() || !s.p1.allFinite() || !std::isfinite(s.sigma)) std::abort();
    if (s.line <= previous || static_cast<std::size_t>(s.line) > lines) std::abort();
    previous = s.line;
  }
  return 0;
}
