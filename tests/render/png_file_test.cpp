/// @file
/// @brief writePng / readPng: exact round trip, atomic output, clear errors for unwritable folders and bad files.
#include "sdfccd/render/png_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "sdfccd/error.h"

namespace sdfccd::render {
namespace {

std::filesystem::path scratchFolder(const std::string& name) {
  const auto folder =
      std::filesystem::temp_directory_path() / ("sdfccd_render_test_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

RgbImage gradient(int width, int height) {
  RgbImage image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = image.at(x, y);
      p[0] = static_cast<std::uint8_t>(x * 7);
      p[1] = static_cast<std::uint8_t>(y * 13);
      p[2] = static_cast<std::uint8_t>((x + y) * 3);
    }
  return image;
}

TEST(PngFile, RoundTripIsExact) {
  const auto folder = scratchFolder("roundtrip");
  const RgbImage image = gradient(37, 23);
  writePng((folder / "a.png").string(), image);
  const RgbImage back = readPng((folder / "a.png").string());
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 23);
  EXPECT_EQ(back.pixels, image.pixels);
  // Nothing but the output is left in the folder (the temporary file was renamed).
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), std::filesystem::directory_iterator()), 1);
  std::filesystem::remove_all(folder);
}

TEST(PngFile, UnwritableFolderIsAClearError) {
  const auto folder = scratchFolder("unwritable");
  const RgbImage image = gradient(8, 8);
  // A missing folder, and a "folder" that is a regular file (fails even for root, unlike permissions).
  EXPECT_THROW(writePng((folder / "no_such_folder" / "a.png").string(), image), Error);
  std::ofstream(folder / "file.txt") << "x";
  try {
    writePng((folder / "file.txt" / "a.png").string(), image);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a.png"), std::string::npos) << e.what();
  }
  EXPECT_THROW(writePng((folder / "empty.png").string(), RgbImage()), Error);
  EXPECT_FALSE(std::filesystem::exists(folder / "empty.png"));
  std::filesystem::remove_all(folder);
}

TEST(PngFile, MissingOrCorruptFileIsAClearError) {
  const auto folder = scratchFolder("corrupt");
  EXPECT_THROW(readPng((folder / "missing.png").string()), Error);
  std::ofstream(folder / "text.png") << "not a png at all";
  EXPECT_THROW(readPng((folder / "text.png").string()), Error);
  // A real PNG cut in half.
  writePng((folder / "whole.png").string(), gradient(64, 64));
  std::ifstream in(folder / "whole.png", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(folder / "half.png", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_THROW(readPng((folder / "half.png").string()), Error);
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace sdfccd::render
