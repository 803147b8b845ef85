/// @file
/// @brief AtomicFile: write an output next to its destination and rename it into place only when complete.
///
/// @details An error (exception, full disk, bad data) while writing never leaves a half-written output:
/// the temporary file is removed by the destructor unless commit() succeeded. rename() within one folder
/// is atomic on POSIX file systems.
#pragma once

#include <fstream>
#include <string>

namespace sdfccd {

class AtomicFile {
 public:
  /// Opens "<path>.tmp-<pid>-<n>" for writing (binary). Throws sdfccd::Error if it cannot be created.
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ofstream& stream() { return m_stream; }
  /// Flushes, checks for write errors and renames onto the destination. Throws sdfccd::Error on failure.
  void commit();
  const std::string& path() const { return m_path; }

 private:
  std::string m_path;
  std::string m_tempPath;
  std::ofstream m_stream;
  bool m_committed = false;
};

/// Writes `contents` to `path` atomically.
void writeFileAtomically(const std::string& path, const std::string& contents);

}  // namespace sdfccd
