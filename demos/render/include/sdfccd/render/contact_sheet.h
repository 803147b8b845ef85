/// @file
/// @brief makeContactSheet: frames of a run side by side in one picture, row by row in time order.
#pragma once

#include <vector>

#include "sdfccd/render/rgb_image.h"

namespace sdfccd::render {

/// Layout of a contact sheet.
struct ContactSheetSettings {
  int columns = 0;                            ///< 0 = ceil(sqrt(number of frames))
  int padding = 4;                            ///< pixels between and around frames
  std::uint8_t background[3] = {40, 40, 44};  ///< colour between frames
};

/// Which of `frameCount` frames a sheet of `cells` cells shows: evenly spaced, first and last included, in order
/// and without repeats (fewer than `cells` when there are fewer frames).
std::vector<int> evenlySpacedFrames(int frameCount, int cells);

/// Places `frames` (all of one size) on a grid, left to right then top to bottom. Throws sdfccd::Error if there
/// are no frames or their sizes differ.
RgbImage makeContactSheet(const std::vector<RgbImage>& frames, const ContactSheetSettings& settings = {});

}  // namespace sdfccd::render
