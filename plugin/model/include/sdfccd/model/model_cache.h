/// @file
/// @brief ModelCache: the one on-disk cache of what is slow to build from a mesh (distance fields, point shells),
/// shared by body models (body_model.h) and haptic scenes (sdfccd/haptics/haptic_scene.h).
///
/// @details An entry is a file "<folder>/<name>-<key>.<ext>": `name` says what it was built from (a mesh file's
/// stem), `key` is a 64-bit FNV-1a (sdfccd/fnv1a.h) of the content it was built from and of the build
/// parameters, written as 16 hex digits, so a changed mesh or parameter never hits a stale entry. Fields are
/// stored in the native .sdf format, shells as .ply; both are written atomically (OutputFile), so an
/// interrupted build never leaves a half-written entry. An entry that fails to load (damaged, truncated) is
/// reported with one line on stderr ("sdfccd: warning: damaged cache entry '<file>' (...); rebuilding it"), then
/// rebuilt and overwritten; a cache that cannot be written only costs the next run the build (the tools check
/// the folder first: checkModelCacheWritable, model_cache_folder.h).
///
/// Thread safety: the cache holds no state beyond its folder; two processes building the same entry at once
/// both write complete files, and the last rename wins.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "sdfccd/field/sdf_grid.h"
#include "sdfccd/fnv1a.h"
#include "sdfccd/shell/point_shell.h"

namespace sdfccd {

/// The key of a cache entry: FNV-1a over every part added, in order.
class ModelCacheKey {
 public:
  ModelCacheKey& add(const void* data, std::size_t size) {
    m_hash = fnv1a(data, size, m_hash);
    return *this;
  }
  ModelCacheKey& add(std::string_view text) { return add(text.data(), text.size()); }
  std::uint64_t value() const { return m_hash; }
  /// The 16 lower-case hex digits used in file names.
  std::string hex() const;

 private:
  std::uint64_t m_hash = kFnv1aOffset;
};

class ModelCache {
 public:
  /// A cache in `folder` (created on the first store); "" disables it (every call builds).
  explicit ModelCache(std::string folder) : m_folder(std::move(folder)) {}

  bool enabled() const { return !m_folder.empty(); }
  const std::string& folder() const { return m_folder; }
  /// "<folder>/<name>-<key>.<extension>" (no check that it exists).
  std::string entryPath(const std::string& name, const ModelCacheKey& key, const std::string& extension) const;

  /// The field of entry (name, key): loaded when present and intact, else built by `build` and stored.
  std::shared_ptr<const SdfGrid> field(const std::string& name, const ModelCacheKey& key,
                                       const std::function<std::shared_ptr<const SdfGrid>()>& build) const;
  /// The shell of entry (name, key): loaded when present and intact, else built by `build` and stored.
  PointShell shell(const std::string& name, const ModelCacheKey& key, const std::function<PointShell()>& build) const;

 private:
  std::string m_folder;
};

}  // namespace sdfccd
