/// @file
/// @brief ScratchFolder: a private folder for what external programs write (gnuplot's PNG, ffmpeg's video,
/// their logs and scripts), whose results are then moved to the user's outputs through OutputFile.
///
/// @details gnuplot and ffmpeg open their outputs by name, following links, so they must never write at a
/// predictable name in a folder another user can write to. The scratch folder is made
/// by mkdtemp(3) under $TMPDIR (else /tmp): an unpredictable name, mode 0700, ours alone. The destructor
/// removes it with everything in it. A finished file goes to its output with moveToOutput(), which has the
/// OutputFile policy: the user's link followed, the target's mode kept, a device written in place, atomic.
#pragma once

#include <string>

namespace sdfccd::cli {

/// See the file comment. Errors throw sdfccd::Error with one line.
class ScratchFolder {
 public:
  ScratchFolder();
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  /// The folder.
  const std::string& path() const { return m_path; }
  /// `path()/name`.
  std::string file(const std::string& name) const { return m_path + "/" + name; }

 private:
  std::string m_path;
};

/// Copies the finished file `scratchFile` to `output` through an OutputFile, then removes it.
void moveToOutput(const std::string& scratchFile, const std::string& output);

}  // namespace sdfccd::cli
