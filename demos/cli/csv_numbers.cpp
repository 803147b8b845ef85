/// @file
/// @brief The numeric CSV lines of the query commands (see csv_numbers.h).
#include "cli/csv_numbers.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <istream>

#include "sdfccd/error.h"

namespace sdfccd::cli {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

// Input size limits: a record is a few numbers, so a longer line or more records than any experiment needs is
// not a segments or motions file (e.g. /dev/zero, which has no newline and would fill memory). One line each.
constexpr std::size_t kMaxLineBytes = 4096;
constexpr std::size_t kMaxRecords = 20'000'000;

/// std::getline with a length limit: false at the end of the input; throws when a line exceeds kMaxLineBytes.
bool readBoundedLine(std::istream& in, std::string& line, const std::string& path, int lineNumber) {
  static thread_local char buffer[kMaxLineBytes + 1];
  in.getline(buffer, sizeof buffer);
  const std::streamsize got = in.gcount();
  if (in.fail() && !in.eof() && !in.bad() && got == static_cast<std::streamsize>(kMaxLineBytes)) {
    throw Error(path + ":" + std::to_string(lineNumber) + ": line longer than " + std::to_string(kMaxLineBytes) +
                " bytes (not a CSV of numbers)");
  }
  if (got == 0 && !in) return false;  // nothing left (or a read error, reported by the caller)
  line.assign(buffer);
  // A NUL byte ends the C string early: the line is not text.
  const std::size_t stored = static_cast<std::size_t>(got) - (in.eof() ? 0 : 1);
  if (line.size() != stored) {
    throw Error(path + ":" + std::to_string(lineNumber) + ": holds a NUL byte (not a CSV of numbers)");
  }
  return true;
}

}  // namespace

std::vector<CsvNumberLine> readCsvNumberLines(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw Error("cannot read " + what + " file '" + path + "'");
  std::vector<CsvNumberLine> lines;
  std::string line;
  for (int lineNumber = 1; readBoundedLine(in, line, path, lineNumber); ++lineNumber) {
    if (lines.size() >= kMaxRecords) {
      throw Error(path + ":" + std::to_string(lineNumber) + ": more than " + std::to_string(kMaxRecords) +
                  " records (split the file)");
    }
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    CsvNumberLine record;
    record.lineNumber = lineNumber;
    record.where = path + ":" + std::to_string(lineNumber) + ": ";
    std::size_t start = 0;
    for (;;) {
      const std::size_t comma = text.find(',', start);
      const std::string field =
          trim(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (field.empty()) throw Error(record.where + "empty value " + std::to_string(record.values.size() + 1));
      errno = 0;
      char* end = nullptr;
      const double v = std::strtod(field.c_str(), &end);
      if (end != field.c_str() + field.size()) throw Error(record.where + "'" + field + "' is not a number");
      if (!std::isfinite(v) || errno == ERANGE) throw Error(record.where + "value '" + field + "' is not finite");
      record.values.push_back(v);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    lines.push_back(std::move(record));
  }
  if (in.bad()) throw Error("error reading " + what + " file '" + path + "'");
  return lines;
}

void appendCsvNumber(std::string& out, double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  out += buffer;
}

}  // namespace sdfccd::cli
