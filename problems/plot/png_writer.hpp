#pragma once
// RGB images and their PNG files (8-bit RGB, compressed by libpng). A plot of 800 x 500
// pixels, mostly background, takes tens of kilobytes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tailor {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};
inline constexpr Rgb kBlack{0, 0, 0};

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

// The complete PNG file of `image`; throws std::runtime_error with libpng's message if
// encoding fails.
std::vector<std::uint8_t> encode_png(const RgbImage& image);
// Writes encode_png(image) to `path`; throws std::runtime_error naming the path on failure.
void write_png(const std::string& path, const RgbImage& image);

}  // namespace tailor
