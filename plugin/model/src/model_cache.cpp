/// @file
/// @brief ModelCache: entries named by content key, loaded when intact, else built and stored (model_cache.h).
#include "sdfccd/model/model_cache.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "sdfccd/error.h"
#include "sdfccd/field/sdf_file.h"

namespace sdfccd {
namespace {

/// Loads the entry at `path` with `load`; false when it is absent or does not load. A damaged entry (truncated,
/// overwritten, a header claiming more than memory holds) is never trusted: it is reported with one line on
/// stderr naming the file, and the caller rebuilds and overwrites it.
template <class T, class Load>
bool tryLoad(const std::string& path, Load&& load, T& out) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return false;
  try {
    out = load(path);
    return true;
  } catch (const std::exception& e) {  // sdfccd::Error from the loaders, std::bad_alloc from an absurd header
    std::string reason = e.what();
    std::replace(reason.begin(), reason.end(), '\n', ' ');
    std::fprintf(stderr, "sdfccd: warning: damaged cache entry '%s' (%s); rebuilding it\n", path.c_str(),
                 reason.c_str());
    return false;
  }
}

/// Stores an entry with `save`, best effort: a read-only or full disk only costs the next run the build.
template <class Save>
void tryStore(const std::string& folder, Save&& save) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  try {
    save();
  } catch (const Error&) {
  }
}

}  // namespace

std::string ModelCacheKey::hex() const {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(m_hash));
  return text;
}

std::string ModelCache::entryPath(const std::string& name, const ModelCacheKey& key,
                                  const std::string& extension) const {
  return (std::filesystem::path(m_folder) / (name + "-" + key.hex() + "." + extension)).string();
}

std::shared_ptr<const SdfGrid> ModelCache::field(const std::string& name, const ModelCacheKey& key,
                                                 const std::function<std::shared_ptr<const SdfGrid>()>& build) const {
  if (!enabled()) return build();
  const std::string path = entryPath(name, key, "sdf");
  std::shared_ptr<const SdfGrid> grid;
  if (tryLoad(
          path, [](const std::string& p) { return std::make_shared<const SdfGrid>(loadSdf(p)); }, grid)) {
    return grid;
  }
  grid = build();
  tryStore(m_folder, [&] { saveSdf(path, *grid, SdfFileFormat::Native); });
  return grid;
}

PointShell ModelCache::shell(const std::string& name, const ModelCacheKey& key,
                             const std::function<PointShell()>& build) const {
  if (!enabled()) return build();
  const std::string path = entryPath(name, key, "ply");
  PointShell shell;
  if (tryLoad(
          path, [](const std::string& p) { return loadShell(p); }, shell))
    return shell;
  shell = build();
  tryStore(m_folder, [&] { saveShell(shell, path); });
  return shell;
}

}  // namespace sdfccd
