/// @file
/// @brief Files of comma-separated numbers (csv_numbers.h): bounded line reading, then the numbers.
#include "sdfccd/csv_numbers.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

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
// line exceeds kMaxCsvLineBytes, so an endless stream without newlines never fills memory.
bool readBoundedLine(std::istream& in, std::string& out, const std::string& where) {
  out.clear();
  std::streambuf* buffer = in.rdbuf();
  bool any = false;
  for (;;) {
    const int c = buffer->sbumpc();
    if (c == std::char_traits<char>::eof()) return any;
    any = true;
    if (c == '\n') return true;
    if (out.size() >= kMaxCsvLineBytes) {
      throw Error(where + "line longer than " + std::to_string(kMaxCsvLineBytes) + " bytes");
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

std::vector<CsvNumberLine> parseCsvNumberLines(std::istream& in, const std::string& name, std::size_t maxRecords,
                                               const std::string& what) {
  std::vector<CsvNumberLine> records;
  std::string line;
  for (int lineNumber = 1;; ++lineNumber) {
    const std::string where = name + ":" + std::to_string(lineNumber) + ": ";
    if (!readBoundedLine(in, line, where)) break;
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    if (records.size() >= maxRecords) throw Error(where + "more than " + std::to_string(maxRecords) + " " + what);
    records.push_back({lineNumber, where, parseNumbers(text, where)});
  }
  if (in.bad()) throw Error("error reading " + what + " file '" + name + "'");
  return records;
}

}  // namespace sdfccd
