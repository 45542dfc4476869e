#include "problems/plot/png_writer.hpp"

#include <png.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "forward/core/atomic_file.hpp"

namespace tailor {

RgbImage::RgbImage(int width, int height, Rgb background) : width_(width), height_(height) {
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("RgbImage: width and height must be positive, got " + std::to_string(width) +
                                " x " + std::to_string(height));
  pixels_.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  for (std::size_t i = 0; i < pixels_.size(); i += 3) {
    pixels_[i] = background.r;
    pixels_[i + 1] = background.g;
    pixels_[i + 2] = background.b;
  }
}

Rgb RgbImage::at(int x, int y) const {
  if (!contains(x, y))
    throw std::out_of_range("RgbImage::at(" + std::to_string(x) + ", " + std::to_string(y) + ") outside " +
                            std::to_string(width_) + " x " + std::to_string(height_));
  const std::size_t i = (static_cast<std::size_t>(y) * width_ + x) * 3;
  return {pixels_[i], pixels_[i + 1], pixels_[i + 2]};
}

void RgbImage::set(int x, int y, Rgb colour) {
  if (!contains(x, y)) return;
  const std::size_t i = (static_cast<std::size_t>(y) * width_ + x) * 3;
  pixels_[i] = colour.r;
  pixels_[i + 1] = colour.g;
  pixels_[i + 2] = colour.b;
}

void RgbImage::fill_rect(int x0, int y0, int x1, int y1, Rgb colour) {
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, width_ - 1);
  y1 = std::min(y1, height_ - 1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) set(x, y, colour);
}

std::vector<std::uint8_t> encode_png(const RgbImage& image) {
  // libpng's simplified API: it handles its own errors (no longjmp through this code) and
  // reports them in `png.message`.
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width());
  png.height = static_cast<png_uint_32>(image.height());
  png.format = PNG_FORMAT_RGB;
  // The bound is the size of an uncompressed file; the compressed one is written into it.
  png_alloc_size_t size = PNG_IMAGE_PNG_SIZE_MAX(png);
  std::vector<std::uint8_t> out(size);
  const bool written = png_image_write_to_memory(&png, out.data(), &size, /*convert_to_8bit=*/0,
                                                 image.pixels().data(), /*row_stride=*/0, nullptr) != 0;
  const std::string message = png.message;
  png_image_free(&png);
  if (!written) throw std::runtime_error("PNG encoding failed: " + message);
  out.resize(size);
  return out;
}

void write_png(const std::string& path, const RgbImage& image) {
  const std::vector<std::uint8_t> bytes = encode_png(image);
  AtomicFile out(path);
  out.write(bytes.data(), bytes.size());
  out.commit();
}

}  // namespace tailor
