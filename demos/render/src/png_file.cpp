/// @file
/// @brief writePng / readPng through libpng's simplified (png_image) API.
#include "sdfccd/render/png_file.h"

#include <png.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "sdfccd/error.h"
#include "sdfccd/output_file.h"

namespace sdfccd::render {

void writePng(const std::string& path, const RgbImage& image) {
  if (image.empty() || image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * 3) {
    throw Error("cannot write '" + path + "': empty or inconsistent image");
  }
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  // First call sizes the buffer, second encodes.
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&png, nullptr, &size, 0, image.pixels.data(), 0, nullptr)) {
    const std::string why = png.message;
    png_image_free(&png);
    throw Error("cannot encode PNG '" + path + "': " + why);
  }
  std::string bytes(size, '\0');
  if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, image.pixels.data(), 0, nullptr)) {
    const std::string why = png.message;
    png_image_free(&png);
    throw Error("cannot encode PNG '" + path + "': " + why);
  }
  bytes.resize(size);
  writeOutputFile(path, bytes);
}

RgbImage readPng(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open '" + path + "': " + std::strerror(errno));
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size())) {
    const std::string why = png.message;
    png_image_free(&png);
    throw Error("cannot read PNG '" + path + "': " + why);
  }
  png.format = PNG_FORMAT_RGB;
  RgbImage image(static_cast<int>(png.width), static_cast<int>(png.height));
  png_color black{0, 0, 0};
  if (!png_image_finish_read(&png, &black, image.pixels.data(), 0, nullptr)) {
    const std::string why = png.message;
    png_image_free(&png);
    throw Error("cannot read PNG '" + path + "': " + why);
  }
  return image;
}

}  // namespace sdfccd::render
