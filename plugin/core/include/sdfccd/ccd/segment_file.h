/// @file
/// @brief The segment file of `sdfccd query`: one segment per line, `x0,y0,z0,x1,y1,z1[,sigma]`.
///
/// @details Values are separated by commas (spaces and tabs around them ignored); blank lines and lines
/// starting with `#` are skipped. Every value must be a finite number (strtod syntax, no overflow). Errors are
/// one-line sdfccd::Error messages starting with `NAME:LINE: `. The input is bounded, so that a stream such as
/// /dev/zero ends with an error instead of exhausting memory: a line may hold at most kMaxSegmentLineBytes
/// bytes and a file at most kMaxSegments segments.
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <vector>

#include "sdfccd/csv_numbers.h"
#include "sdfccd/math_types.h"

namespace sdfccd {

/// Longest accepted line, in bytes (without its newline).
constexpr std::size_t kMaxSegmentLineBytes = kMaxCsvLineBytes;
/// Most segments accepted in one file.
constexpr std::size_t kMaxSegments = 10'000'000;

/// One segment of the file.
struct SegmentRecord {
  Vec3 p0 = Vec3::Zero();
  Vec3 p1 = Vec3::Zero();
  double sigma = 0.0;  ///< the 7th value, or the default sigma
  int line = 0;        ///< 1-based line number
};

/// Parses every segment of `in`; `name` prefixes the errors, `defaultSigma` fills lines without a 7th value.
/// Throws sdfccd::Error on a malformed line, a value that is not a finite number, a line over
/// kMaxSegmentLineBytes, more than kMaxSegments segments, or a read error.
std::vector<SegmentRecord> parseSegments(std::istream& in, const std::string& name, double defaultSigma);

/// Reads the segment file at `path` (see parseSegments). Throws sdfccd::Error ("cannot read segments file
/// 'path'") when it cannot be opened.
std::vector<SegmentRecord> readSegmentFile(const std::string& path, double defaultSigma);

}  // namespace sdfccd
