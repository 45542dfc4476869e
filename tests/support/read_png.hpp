#pragma once
// Reads a PNG file with libpng (its simplified API), for tests that check what a plot shows.
// libpng checks the structure on the way (signature, chunk CRCs, the zlib stream); a file it
// cannot read is a test failure with libpng's message.
#include <png.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "problems/plot/png_writer.hpp"

namespace tailor::testing {

struct ReadPng {
  std::string error;  // empty when the file was read
  std::uint32_t width = 0, height = 0;
  std::uint32_t colour_type = 0;  // png_image format flags as stored in the file
  std::size_t file_size = 0;
  std::vector<std::uint8_t> rgb;  // width * height * 3, row-major, top row first
  Rgb pixel(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x)) * 3;
    return {rgb.at(i), rgb.at(i + 1), rgb.at(i + 2)};
  }
};

inline ReadPng read_png(const std::string& path) {
  ReadPng out;
  std::ifstream in(path, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  out.file_size = bytes.size();
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size())) {
    out.error = png.message;
    return out;
  }
  out.width = png.width;
  out.height = png.height;
  out.colour_type = png.format;
  png.format = PNG_FORMAT_RGB;
  out.rgb.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, out.rgb.data(), 0, nullptr)) out.error = png.message;
  png_image_free(&png);
  return out;
}

}  // namespace tailor::testing
