/// @file
/// @brief RgbImage: an 8-bit RGB picture in memory (row 0 at the top), with the few operations the tools need.
#pragma once

#include <cstdint>
#include <vector>

namespace sdfccd::render {

/// An 8-bit RGB image, rows from top to bottom, 3 bytes per pixel.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  ///< width * height * 3 bytes, row-major from the top-left pixel

  RgbImage() = default;
  /// An image filled with one colour (components 0..255).
  RgbImage(int inWidth, int inHeight, std::uint8_t r = 0, std::uint8_t g = 0, std::uint8_t b = 0);

  bool empty() const { return width <= 0 || height <= 0; }
  /// Pointer to the 3 bytes of pixel (x, y); no bounds check.
  std::uint8_t* at(int x, int y) { return pixels.data() + 3 * (static_cast<std::size_t>(y) * width + x); }
  const std::uint8_t* at(int x, int y) const { return pixels.data() + 3 * (static_cast<std::size_t>(y) * width + x); }
};

/// Averages `factor` x `factor` blocks (supersampling anti-aliasing). `image` dimensions must be multiples of
/// `factor`.
RgbImage downsample(const RgbImage& image, int factor);

/// Copies `source` into `ioTarget` with its top-left corner at (x, y), clipped to the target.
void blit(const RgbImage& source, int x, int y, RgbImage& ioTarget);

/// The largest absolute difference of any channel of any pixel; images of different sizes differ by 255.
int maxChannelDifference(const RgbImage& a, const RgbImage& b);

}  // namespace sdfccd::render
