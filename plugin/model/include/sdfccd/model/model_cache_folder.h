/// @file
/// @brief Where the model cache (model_cache.h) lives: the user's cache folder, never the current folder, checked
/// writable before any work.
#pragma once

#include <string>

namespace sdfccd {

/// The default cache folder of the tools: $XDG_CACHE_HOME/sdfccd when XDG_CACHE_HOME is set to an absolute path
/// (the XDG Base Directory rule: a relative value is ignored), else $HOME/.cache/sdfccd; "" (no cache) when
/// neither is available.
std::string defaultModelCacheFolder();

/// The folder to use: `given` when the user passed --cache (even "", which disables the cache), else
/// defaultModelCacheFolder().
std::string modelCacheFolder(const std::string* given);

/// Creates `folder` if needed and proves it writable by creating (O_EXCL) and removing a probe file in it; throws
/// sdfccd::Error with one line naming the folder and the reason otherwise ("" is a disabled cache: no check).
/// Called before any build, so an unwritable cache fails at once, not after minutes of work.
void checkModelCacheWritable(const std::string& folder);

}  // namespace sdfccd
