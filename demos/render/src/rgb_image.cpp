/// @file
/// @brief RgbImage: construction, block downsampling, blitting and comparison.
#include "sdfccd/render/rgb_image.h"

#include <algorithm>
#include <cstdlib>

#include "sdfccd/error.h"

namespace sdfccd::render {

RgbImage::RgbImage(int inWidth, int inHeight, std::uint8_t r, std::uint8_t g, std::uint8_t b)
    : width(inWidth), height(inHeight) {
  if (inWidth < 0 || inHeight < 0) throw Error("image: negative size");
  pixels.resize(static_cast<std::size_t>(inWidth) * inHeight * 3);
  for (std::size_t i = 0; i < pixels.size(); i += 3) {
    pixels[i] = r;
    pixels[i + 1] = g;
    pixels[i + 2] = b;
  }
}

RgbImage downsample(const RgbImage& image, int factor) {
  if (factor < 1 || image.width % factor != 0 || image.height % factor != 0) {
    throw Error("image: cannot downsample by " + std::to_string(factor));
  }
  if (factor == 1) return image;
  RgbImage result(image.width / factor, image.height / factor);
  const int count = factor * factor;
  for (int y = 0; y < result.height; ++y) {
    for (int x = 0; x < result.width; ++x) {
      int sum[3] = {0, 0, 0};
      for (int dy = 0; dy < factor; ++dy) {
        for (int dx = 0; dx < factor; ++dx) {
          const std::uint8_t* p = image.at(x * factor + dx, y * factor + dy);
          for (int c = 0; c < 3; ++c) sum[c] += p[c];
        }
      }
      std::uint8_t* q = result.at(x, y);
      for (int c = 0; c < 3; ++c) q[c] = static_cast<std::uint8_t>((sum[c] + count / 2) / count);
    }
  }
  return result;
}

void blit(const RgbImage& source, int x, int y, RgbImage& ioTarget) {
  const int x0 = std::max(0, x);
  const int x1 = std::min(ioTarget.width, x + source.width);
  if (x1 <= x0) return;
  for (int row = std::max(0, y); row < std::min(ioTarget.height, y + source.height); ++row) {
    std::copy_n(source.at(x0 - x, row - y), 3 * (x1 - x0), ioTarget.at(x0, row));
  }
}

int maxChannelDifference(const RgbImage& a, const RgbImage& b) {
  if (a.width != b.width || a.height != b.height || a.pixels.size() != b.pixels.size()) return 255;
  int worst = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) worst = std::max(worst, std::abs(a.pixels[i] - b.pixels[i]));
  return worst;
}

}  // namespace sdfccd::render
