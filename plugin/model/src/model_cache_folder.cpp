/// @file
/// @brief The model cache's folder: the XDG default and the writability probe (model_cache_folder.h).
#include "sdfccd/model/model_cache_folder.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>

#include "sdfccd/error.h"

namespace sdfccd {

std::string defaultModelCacheFolder() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg != nullptr && xdg[0] == '/') return (std::filesystem::path(xdg) / "sdfccd").string();
  const char* home = std::getenv("HOME");
  if (home != nullptr && home[0] == '/') return (std::filesystem::path(home) / ".cache" / "sdfccd").string();
  return {};
}

std::string modelCacheFolder(const std::string* given) {
  return given != nullptr ? *given : defaultModelCacheFolder();
}

void checkModelCacheWritable(const std::string& folder) {
  if (folder.empty()) return;
  const std::string what = "cache folder '" + folder + "'";
  const std::string hint = " (pass --cache DIR for another folder, or --cache \"\" for none)";
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) throw Error(what + " cannot be created: " + ec.message() + hint);
  if (!std::filesystem::is_directory(folder, ec)) throw Error(what + " is not a folder" + hint);
  // A probe with an unpredictable name, created exclusively (never through a planted link), then removed.
  std::random_device random;
  const std::string probe =
      (std::filesystem::path(folder) / (".write-probe-" + std::to_string(random()) + std::to_string(::getpid())))
          .string();
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) throw Error(what + " is not writable: " + std::strerror(errno) + hint);
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace sdfccd
