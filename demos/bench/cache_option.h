/// @file
/// @brief `--cache DIR` of `sdfccd bench ...` and `sdfccd report`: the model cache folder with the same default as
/// simulate and haptics ($XDG_CACHE_HOME/sdfccd, else ~/.cache/sdfccd; sdfccd/model/model_cache_folder.h), never
/// ./out/cache under the current folder.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "sdfccd/model/model_cache_folder.h"

namespace sdfccd::cli {

/// A `--cache` option whose value is kept in `folder`. `what` says what is cached (for the help text).
inline CLI::Option* addCacheOption(CLI::App& command, std::string& folder, const std::string& what) {
  return command.add_option("--cache", folder,
                            what + " (\"\" disables; default $XDG_CACHE_HOME/sdfccd, else ~/.cache/sdfccd)");
}

/// The folder to use: the given --cache (even "", no cache), else the default; checked writable before any work.
inline std::string resolveCacheOption(const CLI::Option* option, const std::string& given) {
  const std::string folder = modelCacheFolder(option != nullptr && option->count() > 0 ? &given : nullptr);
  checkModelCacheWritable(folder);
  return folder;
}

}  // namespace sdfccd::cli
