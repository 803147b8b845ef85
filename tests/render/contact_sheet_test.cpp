/// @file
/// @brief makeContactSheet and evenlySpacedFrames: layout, order, first/last frames, errors.
#include "sdfccd/render/contact_sheet.h"

#include <gtest/gtest.h>

#include "sdfccd/error.h"

namespace sdfccd::render {
namespace {

TEST(ContactSheet, EvenlySpacedFramesIncludeFirstAndLast) {
  EXPECT_EQ(evenlySpacedFrames(100, 5), (std::vector<int>{0, 25, 50, 74, 99}));
  EXPECT_EQ(evenlySpacedFrames(3, 9), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(evenlySpacedFrames(7, 1), (std::vector<int>{0}));
  EXPECT_TRUE(evenlySpacedFrames(0, 4).empty());
  const std::vector<int> many = evenlySpacedFrames(2000, 12);
  EXPECT_EQ(many.size(), 12u);
  EXPECT_EQ(many.front(), 0);
  EXPECT_EQ(many.back(), 1999);
}

TEST(ContactSheet, PlacesFramesRowByRow) {
  std::vector<RgbImage> frames;
  for (int i = 0; i < 5; ++i) frames.emplace_back(10, 6, static_cast<std::uint8_t>(50 * i), 7, 9);
  ContactSheetSettings settings;
  settings.padding = 2;
  const RgbImage sheet = makeContactSheet(frames, settings);
  // ceil(sqrt(5)) = 3 columns, 2 rows.
  EXPECT_EQ(sheet.width, 3 * 12 + 2);
  EXPECT_EQ(sheet.height, 2 * 8 + 2);
  for (int i = 0; i < 5; ++i) {
    const int x = 2 + (i % 3) * 12 + 5;
    const int y = 2 + (i / 3) * 8 + 3;
    EXPECT_EQ(sheet.at(x, y)[0], 50 * i) << "frame " << i;
  }
  EXPECT_EQ(sheet.at(0, 0)[0], settings.background[0]);
  // The empty sixth cell is background.
  EXPECT_EQ(sheet.at(2 + 2 * 12 + 5, 2 + 8 + 3)[0], settings.background[0]);
}

TEST(ContactSheet, BadFramesAreClearErrors) {
  EXPECT_THROW(makeContactSheet({}), Error);
  EXPECT_THROW(makeContactSheet({RgbImage(4, 4), RgbImage(5, 4)}), Error);
}

}  // namespace
}  // namespace sdfccd::render
