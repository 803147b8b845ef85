/// @file
/// @brief Figures of the paper (Xu & Barbic) that more than one report section prints beside ours.
#pragma once

namespace sdfccd::cli {

/// Fig. 10a: the continuous penalty model's largest stable timestep over the discrete model's.
inline constexpr double kPaperTimestepRatio = 3.0;

}  // namespace sdfccd::cli
