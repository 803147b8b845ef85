/// @file
/// @brief makeContactSheet and the choice of evenly spaced frames.
#include "sdfccd/render/contact_sheet.h"

#include <cmath>

#include "sdfccd/error.h"

namespace sdfccd::render {

std::vector<int> evenlySpacedFrames(int frameCount, int cells) {
  std::vector<int> chosen;
  if (frameCount <= 0 || cells <= 0) return chosen;
  if (cells == 1) return {0};
  for (int i = 0; i < cells; ++i) {
    // Rounded to the nearest frame: i = 0 gives the first, i = cells - 1 the last.
    const long long numerator = static_cast<long long>(i) * (frameCount - 1);
    const int frame = static_cast<int>((2 * numerator + (cells - 1)) / (2 * (cells - 1)));
    if (chosen.empty() || frame != chosen.back()) chosen.push_back(frame);
  }
  return chosen;
}

RgbImage makeContactSheet(const std::vector<RgbImage>& frames, const ContactSheetSettings& settings) {
  if (frames.empty()) throw Error("contact sheet: no frames");
  const int width = frames.front().width;
  const int height = frames.front().height;
  for (const RgbImage& frame : frames) {
    if (frame.width != width || frame.height != height || frame.empty()) {
      throw Error("contact sheet: frames must all have the same, non-zero size");
    }
  }
  if (settings.padding < 0) throw Error("contact sheet: negative padding");
  const int count = static_cast<int>(frames.size());
  const int columns = settings.columns > 0 ? std::min(settings.columns, count)
                                           : static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
  const int rows = (count + columns - 1) / columns;
  const int pad = settings.padding;
  RgbImage sheet(columns * (width + pad) + pad, rows * (height + pad) + pad, settings.background[0],
                 settings.background[1], settings.background[2]);
  for (int i = 0; i < count; ++i) {
    blit(frames[static_cast<std::size_t>(i)], pad + (i % columns) * (width + pad), pad + (i / columns) * (height + pad),
         sheet);
  }
  return sheet;
}

}  // namespace sdfccd::render
