/// @file
/// @brief OutputFolder: mkdir -p that remembers what it made, and rmdir of it on failure.
#include "sdfccd/output_folder.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "sdfccd/error.h"
#include "temp_file_registry.h"

namespace sdfccd {

OutputFolder::OutputFolder(std::string path) : m_path(std::move(path)) {
  if (m_path.empty()) throw Error("an output folder path is empty");
  // Each prefix ending before a '/', then the whole path: "a/b/c" -> "a", "a/b", "a/b/c".
  std::vector<std::string> prefixes;
  for (std::size_t slash = m_path.find('/', 1); slash != std::string::npos; slash = m_path.find('/', slash + 1)) {
    if (m_path[slash - 1] != '/') prefixes.push_back(m_path.substr(0, slash));
  }
  prefixes.push_back(m_path);
  try {
    for (const std::string& prefix : prefixes) {
      if (::mkdir(prefix.c_str(), 0777) == 0) {
        m_created.push_back(prefix);
        m_slots.push_back(detail::registerTempFolder(prefix.c_str()));
        continue;
      }
      const int error = errno;
      struct stat info {};
      if (error == EEXIST && ::stat(prefix.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) continue;
      const std::string why = error == EEXIST ? "'" + prefix + "' is not a folder" : std::strerror(error);
      throw Error("cannot create the output folder '" + m_path + "': " + why);
    }
  } catch (...) {
    removeCreated();
    throw;
  }
}

OutputFolder::~OutputFolder() {
  removeCreated();
}

void OutputFolder::removeCreated() {
  for (std::size_t n = m_created.size(); n-- > 0;) {
    ::rmdir(m_created[n].c_str());  // fails, harmlessly, when the run left files in it
    detail::unregisterTempFile(m_slots[n]);
  }
  m_created.clear();
  m_slots.clear();
}

void OutputFolder::keep() {
  for (const int slot : m_slots) detail::unregisterTempFile(slot);
  m_created.clear();
  m_slots.clear();
}

}  // namespace sdfccd
