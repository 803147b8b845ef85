/// @file
/// @brief A progress callback for long work in the core (which never prints on its own).
#pragma once

#include <functional>

namespace sdfccd {

/// Called with the fraction done in [0, 1]; may be called from any worker thread, but never concurrently.
using ProgressCallback = std::function<void(double fractionDone)>;

}  // namespace sdfccd
