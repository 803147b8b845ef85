/// @file
/// @brief MarkdownTable: a GitHub-flavoured Markdown table built row by row, and fmt(): printf-style number
/// formatting into a std::string (for the report's sections).
#pragma once

#include <cstdarg>
#include <cstdio>
#include <string>
#include <vector>

namespace sdfccd::cli {

/// printf-style formatting into a std::string.
#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
inline std::string
fmt(const char* format, ...) {
  va_list args;
  va_start(args, format);
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  std::string out(n > 0 ? static_cast<std::size_t>(n) : 0, '\0');
  if (n > 0) std::vsnprintf(out.data(), out.size() + 1, format, args);
  va_end(args);
  return out;
}

/// A Markdown table: header cells, then rows of the same width (short rows are padded with empty cells).
class MarkdownTable {
 public:
  explicit MarkdownTable(std::vector<std::string> header) : m_header(std::move(header)) {}
  void addRow(std::vector<std::string> row) {
    row.resize(m_header.size());
    m_rows.push_back(std::move(row));
  }
  /// The table text, ending with a newline.
  std::string str() const {
    std::string out = line(m_header);
    out += "|";
    for (std::size_t i = 0; i < m_header.size(); ++i) out += "---|";
    out += "\n";
    for (const auto& row : m_rows) out += line(row);
    return out;
  }

 private:
  static std::string line(const std::vector<std::string>& cells) {
    std::string out = "|";
    for (const std::string& c : cells) out += " " + c + " |";
    return out + "\n";
  }
  std::vector<std::string> m_header;
  std::vector<std::vector<std::string>> m_rows;
};

}  // namespace sdfccd::cli
