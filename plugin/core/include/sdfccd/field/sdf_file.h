/// @file
/// @brief Reading and writing grid SDFs: the native binary format and the plain-text SDFGen layout.
///
/// @details Native format (little-endian, documented in docs/file-formats.md):
/// a 64-byte header (magic "SDFCCD\0\1", version, node counts, origin, spacing, value count), the values as
/// float32 with i fastest, then a 64-bit FNV-1a checksum of header and values.
/// SDFGen text: line 1 `ni nj nk`, line 2 the origin `x y z`, line 3 the spacing `dx`, then ni*nj*nk values
/// with i fastest; value (i,j,k) sits at origin + (i,j,k)*dx.
/// Loading detects the format by content and validates everything; any defect is a one-line sdfccd::Error
/// naming the file. Saving goes through OutputFile: an error never leaves a partial output.
#pragma once

#include <string>

#include "sdfccd/field/sdf_grid.h"

namespace sdfccd {

enum class SdfFileFormat {
  Native,  ///< binary, float32, checksummed
  SdfGen,  ///< plain text (SDFGen by Christopher Batty)
};

/// "native" or "sdfgen".
const char* toString(SdfFileFormat format);
/// Parses "native" or "sdfgen" (throws sdfccd::Error otherwise).
SdfFileFormat parseSdfFileFormat(const std::string& name);
/// SdfGen when `path` ends in ".sdfgen", Native otherwise.
SdfFileFormat sdfFileFormatForPath(const std::string& path);

/// Loads a field in either format (detected by content). Throws sdfccd::Error naming `path` on any defect.
SdfGrid loadSdf(const std::string& path);
/// Writes `grid` atomically. Throws sdfccd::Error on failure (no output file is left behind).
void saveSdf(const std::string& path, const SdfGrid& grid, SdfFileFormat format);
/// Writes in the format sdfFileFormatForPath(path) picks.
inline void saveSdf(const std::string& path, const SdfGrid& grid) {
  saveSdf(path, grid, sdfFileFormatForPath(path));
}

/// In-memory forms of the above (tests, pipes). `name` is used in error messages.
SdfGrid parseSdf(const std::string& bytes, const std::string& name);
std::string serializeSdf(const SdfGrid& grid, SdfFileFormat format);

}  // namespace sdfccd
