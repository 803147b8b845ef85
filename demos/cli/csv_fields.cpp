/// @file
/// @brief csvField / splitCsvRecord / readCsvRecord: RFC 4180 quoting.
#include "cli/csv_fields.h"

namespace sdfccd::cli {
namespace {

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

}  // namespace

std::string csvField(const std::string& text) {
  const bool needsQuotes = text.find_first_of(",\"\n\r") != std::string::npos ||
                           (!text.empty() && (isBlank(text.front()) || isBlank(text.back())));
  if (!needsQuotes) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

std::vector<std::string> splitCsvRecord(const std::string& record) {
  std::vector<std::string> fields;
  std::size_t i = 0;
  const std::size_t n = record.size();
  for (;;) {
    while (i < n && isBlank(record[i])) ++i;
    std::string field;
    if (i < n && record[i] == '"') {
      for (++i; i < n; ++i) {
        if (record[i] != '"') {
          field += record[i];
        } else if (i + 1 < n && record[i + 1] == '"') {
          field += '"';
          ++i;
        } else {
          ++i;
          break;
        }
      }
      while (i < n && record[i] != ',') ++i;  // blanks (or stray text) after the closing quote
    } else {
      const std::size_t begin = i;
      while (i < n && record[i] != ',') ++i;
      std::size_t end = i;
      while (end > begin && isBlank(record[end - 1])) --end;
      field = record.substr(begin, end - begin);
    }
    fields.push_back(std::move(field));
    if (i >= n) break;
    ++i;  // the comma
  }
  return fields;
}

bool readCsvRecord(std::istream& in, std::string& outRecord, int& ioLineNumber) {
  if (!std::getline(in, outRecord)) return false;
  ++ioLineNumber;
  // An odd number of quotes so far: a quoted field goes on past the line break.
  auto quotes = [](const std::string& text) {
    std::size_t count = 0;
    for (const char c : text) count += c == '"' ? 1 : 0;
    return count;
  };
  std::size_t open = quotes(outRecord) % 2;
  for (std::string next; open == 1 && std::getline(in, next); ++ioLineNumber) {
    outRecord += '\n';
    outRecord += next;
    open = (open + quotes(next)) % 2;
  }
  return true;
}

}  // namespace sdfccd::cli
