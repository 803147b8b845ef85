/// @file
/// @brief CSV fields as RFC 4180 has them: csvField() quotes a field for writing, splitCsvRecord() splits a
/// record for reading, readCsvRecord() reads one record (a quoted field may hold a line break).
///
/// @details Names from scene files are data: a body named `a,b` or `say "hi"` must come back from the run's
/// CSV as it went in. A field is quoted when it holds a comma, a quote, a line break or
/// leading or trailing blanks (the reader trims unquoted fields); a quote inside is doubled.
#pragma once

#include <istream>
#include <string>
#include <vector>

namespace sdfccd::cli {

/// `text` as one CSV field: unchanged when it needs no quotes, else in double quotes with `"` doubled.
std::string csvField(const std::string& text);

/// The fields of one record. Unquoted fields are trimmed of blanks; quoted fields are taken verbatim (with
/// `""` read as `"`), and blanks around the quotes are ignored. A trailing comma ends with an empty field.
std::vector<std::string> splitCsvRecord(const std::string& record);

/// Reads one record: a line, joined with the following lines while a quoted field is still open. Returns
/// false at the end of the stream. `ioLineNumber` is advanced by the lines read.
bool readCsvRecord(std::istream& in, std::string& outRecord, int& ioLineNumber);

}  // namespace sdfccd::cli
