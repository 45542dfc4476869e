#pragma once
// A minimal, dependency-free PNG writer: 8-bit RGB, no interlacing, the zlib stream made of
// "stored" (uncompressed) deflate blocks. Files are larger than a compressing encoder's but
// every viewer reads them. CRC-32 and Adler-32 are implemented here.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tailor {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

// Row-major RGB pixels, (0, 0) at the top left.
class RgbImage {
 public:
  // Throws std::invalid_argument unless width and height are positive.
  RgbImage(int width, int height, Rgb background = {255, 255, 255});
  int width() const { return width_; }
  int height() const { return height_; }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  Rgb at(int x, int y) const;                                  // throws std::out_of_range outside the image
  void set(int x, int y, Rgb colour);                          // ignores pixels outside the image
  void fill_rect(int x0, int y0, int x1, int y1, Rgb colour);  // inclusive corners, clipped
  const std::vector<std::uint8_t>& pixels() const { return pixels_; }  // r, g, b per pixel

 private:
  int width_, height_;
  std::vector<std::uint8_t> pixels_;
};

std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc = 0);
std::uint32_t adler32(const std::uint8_t* data, std::size_t size);

// The complete PNG file of `image`.
std::vector<std::uint8_t> encode_png(const RgbImage& image);
// Writes encode_png(image) to `path`; throws std::runtime_error naming the path on failure.
void write_png(const std::string& path, const RgbImage& image);

}  // namespace tailor
