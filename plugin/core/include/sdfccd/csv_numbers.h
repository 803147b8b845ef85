/// @file
/// @brief Files of comma-separated numbers, one record per line: the segment file of `sdfccd query`
/// (ccd/segment_file.h) and the motion file of `sdfccd query-rigid` read their lines here.
///
/// @details Values are separated by commas (spaces and tabs around them ignored); blank lines and lines
/// starting with `#` are skipped. Every value must be a finite number (strtod syntax, no overflow). Errors are
/// one-line sdfccd::Error messages starting with `NAME:LINE: `. The input is bounded, so that a stream such as
/// /dev/zero ends with an error instead of exhausting memory: a line may hold at most kMaxCsvLineBytes bytes,
/// and the caller names the most records it accepts.
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <vector>

namespace sdfccd {

/// Longest accepted line, in bytes (without its newline): a record is a few numbers.
constexpr std::size_t kMaxCsvLineBytes = 4096;

/// One non-blank, non-comment line.
struct CsvNumberLine {
  int lineNumber = 0;          ///< 1-based line number in the input
  std::string where;           ///< "NAME:LINE: ", the prefix of every error about this line
  std::vector<double> values;  ///< the line's values, all finite
};

/// Parses every record of `in`; `name` prefixes the errors and `what` names a record in the error of a file with
/// more than `maxRecords` of them ("more than N segments"). Throws sdfccd::Error on an empty value, a value that
/// is not a finite number, a NUL byte, a line over kMaxCsvLineBytes, too many records, or a read error.
std::vector<CsvNumberLine> parseCsvNumberLines(std::istream& in, const std::string& name, std::size_t maxRecords,
                                               const std::string& what);

}  // namespace sdfccd
