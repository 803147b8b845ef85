/// @file
/// @brief The numeric CSV lines of the query commands (see csv_numbers.h): the core's bounded reader
/// (sdfccd/csv_numbers.h) on a file.
#include "cli/csv_numbers.h"

#include <cstdio>
#include <fstream>

#include "sdfccd/error.h"

namespace sdfccd::cli {
namespace {

// A record is a few numbers: more records than any experiment needs is not a segments or motions file.
constexpr std::size_t kMaxRecords = 20'000'000;

}  // namespace

std::vector<CsvNumberLine> readCsvNumberLines(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read " + what + " file '" + path + "'");
  return parseCsvNumberLines(in, path, kMaxRecords, what);
}

void appendCsvNumber(std::string& out, double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  out += buffer;
}

}  // namespace sdfccd::cli
