/// @file
/// @brief writePng / readPng: RgbImage to and from PNG files through libpng's simplified API.
///
/// @details Writing encodes in memory, then writes atomically (OutputFile: temporary file + rename), so an
/// error never leaves a half-written PNG. libpng's simplified API reports errors through return codes (no
/// setjmp/longjmp across C++ frames).
#pragma once

#include <string>

#include "sdfccd/render/rgb_image.h"

namespace sdfccd::render {

/// Writes `image` to `path` as an 8-bit RGB PNG. Throws sdfccd::Error (naming the file) if the image is empty
/// or the file cannot be written (missing or unwritable folder, full disk).
void writePng(const std::string& path, const RgbImage& image);

/// Reads any PNG as 8-bit RGB (alpha composited on black). Throws sdfccd::Error naming the file if it is
/// missing, not a PNG or corrupt.
RgbImage readPng(const std::string& path);

}  // namespace sdfccd::render
