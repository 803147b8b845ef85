/// @file
/// @brief The numeric CSV lines of the query commands: reading an input file of comma-separated numbers per
/// line, and writing a fraction of the step with 17 significant digits.
///
/// @details `sdfccd query` (segments) and `sdfccd query-rigid` (motions) read the same kind of file: one
/// record per line, values separated by commas (spaces around them ignored), blank lines and lines starting with
/// `#` skipped. Lines are at most 4096 bytes and files at most 20 million records (a longer line, a NUL byte or
/// /dev/zero is one error, not a read until memory runs out). Every value must be a finite number; a bad one gives an
/// sdfccd::Error of one line that names the file and the line (`FILE:LINE: ...`). The caller checks the number of
/// values per record and reports its own errors with the record's `where` prefix, so every error of an input file reads
/// the same.
#pragma once

#include <string>
#include <vector>

#include "sdfccd/csv_numbers.h"

namespace sdfccd::cli {

/// Reads every record of `path`. `what` names the file's role in the error of a missing file ("cannot read
/// `what` file 'path'"). Throws sdfccd::Error on a missing or unreadable file, an empty value, a value that is
/// not a number, or NaN/inf/overflow.
std::vector<CsvNumberLine> readCsvNumberLines(const std::string& path, const std::string& what);

/// Appends `value` with 17 significant digits (printf "%.17g": reads back as the same double).
void appendCsvNumber(std::string& out, double value);

}  // namespace sdfccd::cli
