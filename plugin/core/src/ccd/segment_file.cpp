/// @file
/// @brief The segment file of `sdfccd query` (segment_file.h): bounded line reading, then the numbers.
#include "sdfccd/ccd/segment_file.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "sdfccd/error.h"

namespace sdfccd {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

// Reads one line into `out` (without the newline); false at the end of the input. Stops with an error once a
// line exceeds kMaxSegmentLineBytes, so an endless stream without newlines never fills memory.
bool readBoundedLine(std::istream& in, std::string& out, const std::string& where) {
  out.clear();
  std::streambuf* buffer = in.rdbuf();
  bool any = false;
  for (;;) {
    const int c = buffer->sbumpc();
    if (c == std::char_traits<char>::eof()) return any;
    any = true;
    if (c == '\n') return true;
    if (out.size() >= kMaxSegmentLineBytes) {
      throw Error(where + "line longer than " + std::to_string(kMaxSegmentLineBytes) + " bytes");
    }
    out.push_back(static_cast<char>(c));
  }
}

// The comma-separated finite numbers of one (trimmed, non-empty) line.
std::vector<double> parseNumbers(const std::string& text, const std::string& where) {
  std::vector<double> values;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    const std::string field = trim(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (field.empty()) throw Error(where + "empty value " + std::to_string(values.size() + 1));
    if (field.find('\0') != std::string::npos) throw Error(where + "a value holds a NUL byte");
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(field.c_str(), &end);
    if (end != field.c_str() + field.size()) throw Error(where + "'" + field + "' is not a number");
    if (!std::isfinite(v) || errno == ERANGE) throw Error(where + "value '" + field + "' is not finite");
    values.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return values;
}

}  // namespace

std::vector<SegmentRecord> parseSegments(std::istream& in, const std::string& name, double defaultSigma) {
  std::vector<SegmentRecord> segments;
  std::string line;
  for (int lineNumber = 1;; ++lineNumber) {
    const std::string where = name + ":" + std::to_string(lineNumber) + ": ";
    if (!readBoundedLine(in, line, where)) break;
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    const std::vector<double> values = parseNumbers(text, where);
    if (values.size() != 6 && values.size() != 7) {
      throw Error(where + "expected 6 or 7 comma-separated numbers (x0,y0,z0,x1,y1,z1[,sigma]), got " +
                  std::to_string(values.size()));
    }
    if (segments.size() >= kMaxSegments) {
      throw Error(where + "more than " + std::to_string(kMaxSegments) + " segments");
    }
    segments.push_back({Vec3(values[0], values[1], values[2]), Vec3(values[3], values[4], values[5]),
                        values.size() == 7 ? values[6] : defaultSigma, lineNumber});
  }
  if (in.bad()) throw Error("error reading segments file '" + name + "'");
  return segments;
}

std::vector<SegmentRecord> readSegmentFile(const std::string& path, double defaultSigma) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read segments file '" + path + "'");
  return parseSegments(in, path, defaultSigma);
}

}  // namespace sdfccd
