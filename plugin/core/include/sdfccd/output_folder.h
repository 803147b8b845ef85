/// @file
/// @brief OutputFolder: a command's output folder (a run folder, a report folder) that a failed or interrupted
/// run does not leave behind empty.
///
/// @details The constructor creates the folder and its missing parents (mode 0777 & ~umask, like mkdir -p)
/// and remembers which ones it created. Until keep() is called, those folders are removed again — only if
/// they are empty, deepest first — when the OutputFolder is destroyed (an exception ended the run) or a
/// terminating signal ends the process (see OutputFile for the signals). Files a run wrote stay: a folder is
/// only ever removed by rmdir(2), which refuses a folder that holds anything. A folder that already existed
/// is never removed.
#pragma once

#include <string>
#include <vector>

namespace sdfccd {

/// See the file comment. Errors throw sdfccd::Error with one line naming the folder.
class OutputFolder {
 public:
  /// Creates `path` and its missing parents; an existing folder is fine, an existing non-folder is an error.
  explicit OutputFolder(std::string path);
  /// Without keep(): removes the folders the constructor created, if they are (still) empty.
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  /// The folder as the caller named it.
  const std::string& path() const { return m_path; }
  /// The run succeeded (or has written what it should keep): the folder stays from now on.
  void keep();

 private:
  void removeCreated();

  std::string m_path;
  std::vector<std::string> m_created;  // outermost first
  std::vector<int> m_slots;            // their signal-cleanup slots
};

}  // namespace sdfccd
