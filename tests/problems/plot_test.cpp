// The dependency-free PNG plots: the file structure (signature, chunk CRCs recomputed here
// bitwise, IHDR, the stored-block zlib stream and its Adler-32), known pixels of a rendered
// line plot, log axes with non-positive values, empty series, unwritable paths, and
// DIR/convergence.png of `tailor run`.
#include <gtest/gtest.h>

#include "../support/temp_folder.hpp"
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "problems/inverse_commands.hpp"
#include "problems/plot/convergence_plot.hpp"
#include "problems/plot/line_plot.hpp"
#include "problems/plot/png_writer.hpp"

namespace tailor {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

const std::string kScenes = tailor::testing::kScenesDir;

using TempFolder = tailor::testing::TempFolder;

Bytes read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Bit by bit, independent of the writer's table.
std::uint32_t bitwise_crc32(const std::uint8_t* data, std::size_t size) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) {
    c ^= data[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

std::uint32_t be32(const Bytes& b, std::size_t at) {
  return (std::uint32_t{b.at(at)} << 24) | (std::uint32_t{b.at(at + 1)} << 16) |
         (std::uint32_t{b.at(at + 2)} << 8) | std::uint32_t{b.at(at + 3)};
}

struct DecodedPng {
  std::uint32_t width = 0, height = 0;
  std::vector<std::string> chunk_types;
  Bytes raw;  // the decompressed scanlines, filter bytes included
  Rgb pixel(int x, int y) const {
    const std::size_t row = 1 + 3 * std::size_t{width};
    const std::size_t i = static_cast<std::size_t>(y) * row + 1 + 3 * static_cast<std::size_t>(x);
    return {raw.at(i), raw.at(i + 1), raw.at(i + 2)};
  }
};

Rgb image_pixel(const DecodedPng& png, int x, int y) { return png.pixel(x, y); }
Rgb image_pixel(const RgbImage& image, int x, int y) { return image.at(x, y); }

// Parses a PNG file as written by write_png, checking every structural rule on the way.
DecodedPng decode(const Bytes& file) {
  DecodedPng png;
  const Bytes signature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  EXPECT_GE(file.size(), 8u);
  EXPECT_TRUE(std::equal(signature.begin(), signature.end(), file.begin()));
  Bytes idat;
  std::size_t at = 8;
  while (at < file.size()) {
    const std::uint32_t length = be32(file, at);
    const std::string type(file.begin() + static_cast<std::ptrdiff_t>(at + 4),
                           file.begin() + static_cast<std::ptrdiff_t>(at + 8));
    EXPECT_LE(at + 12 + length, file.size());
    EXPECT_EQ(be32(file, at + 8 + length), bitwise_crc32(file.data() + at + 4, 4 + std::size_t{length}))
        << "CRC of chunk " << type;
    png.chunk_types.push_back(type);
    if (type == "IHDR") {
      EXPECT_EQ(length, 13u);
      png.width = be32(file, at + 8);
      png.height = be32(file, at + 12);
      EXPECT_EQ(file.at(at + 16), 8);  // bit depth
      EXPECT_EQ(file.at(at + 17), 2);  // RGB
    } else if (type == "IDAT") {
      idat.insert(idat.end(), file.begin() + static_cast<std::ptrdiff_t>(at + 8),
                  file.begin() + static_cast<std::ptrdiff_t>(at + 8 + length));
    }
    at += 12 + std::size_t{length};
  }
  EXPECT_EQ(at, file.size());

  // zlib header, stored deflate blocks, Adler-32.
  EXPECT_GE(idat.size(), 6u);
  if (idat.size() < 6) return png;
  EXPECT_EQ(idat[0] & 0x0F, 8);
  EXPECT_EQ((idat[0] * 256 + idat[1]) % 31, 0);
  std::size_t p = 2;
  bool final_block = false;
  while (!final_block && p + 5 <= idat.size()) {
    final_block = (idat[p] & 1) != 0;
    EXPECT_EQ((idat[p] >> 1) & 3, 0) << "not a stored block";
    const std::size_t len = idat[p + 1] | (idat[p + 2] << 8);
    const std::size_t nlen = idat[p + 3] | (idat[p + 4] << 8);
    EXPECT_EQ(len ^ 0xFFFFu, nlen);
    p += 5;
    EXPECT_LE(p + len, idat.size());
    png.raw.insert(png.raw.end(), idat.begin() + static_cast<std::ptrdiff_t>(p),
                   idat.begin() + static_cast<std::ptrdiff_t>(p + len));
    p += len;
  }
  EXPECT_TRUE(final_block);
  EXPECT_EQ(p + 4, idat.size());
  std::uint32_t a = 1, b = 0;
  for (const std::uint8_t v : png.raw) {
    a = (a + v) % 65521;
    b = (b + a) % 65521;
  }
  EXPECT_EQ(be32(idat, p), (b << 16) | a) << "Adler-32";
  return png;
}

// Whether `colour` is at pixel p or one of its 8 neighbours (a sloped line may round either way).
template <class Image>
bool near(const Image& image, const std::optional<std::array<int, 2>>& p, Rgb colour) {
  if (!p) return false;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (image_pixel(image, (*p)[0] + dx, (*p)[1] + dy) == colour) return true;
  return false;
}

constexpr Rgb kWhite{255, 255, 255};
constexpr Rgb kRed{200, 0, 0};
constexpr Rgb kGreen{0, 150, 0};

TEST(Png, ChecksumsMatchTheirStandardCheckValues) {
  const std::string check = "123456789";
  const auto* data = reinterpret_cast<const std::uint8_t*>(check.data());
  EXPECT_EQ(crc32(data, check.size()), 0xCBF43926u);
  EXPECT_EQ(bitwise_crc32(data, check.size()), 0xCBF43926u);
  const std::string wiki = "Wikipedia";
  EXPECT_EQ(adler32(reinterpret_cast<const std::uint8_t*>(wiki.data()), wiki.size()), 0x11E60398u);
}

TEST(Png, SmallImageRoundTrips) {
  TempFolder folder("plot_small");
  RgbImage image(3, 2, {10, 20, 30});
  image.set(2, 1, {1, 2, 3});
  image.set(5, 5, {9, 9, 9});  // outside: ignored
  write_png(folder / "small.png", image);
  const DecodedPng png = decode(read_bytes(folder / "small.png"));
  EXPECT_EQ(png.width, 3u);
  EXPECT_EQ(png.height, 2u);
  EXPECT_EQ(png.chunk_types, (std::vector<std::string>{"IHDR", "IDAT", "IEND"}));
  ASSERT_EQ(png.raw.size(), 2u * (1 + 3 * 3));
  EXPECT_EQ(png.raw[0], 0);  // filter type none
  EXPECT_EQ(png.pixel(0, 0), (Rgb{10, 20, 30}));
  EXPECT_EQ(png.pixel(2, 1), (Rgb{1, 2, 3}));
  EXPECT_THROW(RgbImage(0, 4), std::invalid_argument);
}

TEST(Png, UnwritablePathThrowsNamingIt) {
  const std::string path = "/nonexistent_tailor_folder/sub/plot.png";
  try {
    write_png(path, RgbImage(4, 4));
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  LinePlot plot;
  EXPECT_THROW(write_line_plot_png(path, plot), std::runtime_error);
}

TEST(LinePlotPng, KnownPixelsOfAStraightLine) {
  TempFolder folder("plot_line");
  LinePlot plot;
  plot.title = "Straight (lines)";
  plot.x_label = "x";
  plot.y_label = "y";
  plot.series = {{"y = 5", kRed, {0, 10}, {5, 5}}, {"ramp", kGreen, {0, 3, 7}, {-2.5, 1, 12}}};
  PlotFrame frame;
  const RgbImage image = render_line_plot(plot, &frame);
  write_line_plot_png(folder / "line.png", plot);
  const DecodedPng png = decode(read_bytes(folder / "line.png"));
  ASSERT_EQ(png.width, 800u);
  ASSERT_EQ(png.height, 500u);
  ASSERT_EQ(png.raw.size(), 500u * (1 + 800 * 3));
  for (int y = 0; y < 500; ++y) EXPECT_EQ(png.raw[static_cast<std::size_t>(y) * (1 + 800 * 3)], 0);
  EXPECT_EQ(png.pixel(0, 0), kWhite);
  EXPECT_EQ(png.pixel(799, 499), kWhite);
  EXPECT_EQ(png.pixel(0, 0), image.at(0, 0));

  // The axes hold every point; the horizontal line is red along its length.
  EXPECT_LE(frame.x_min, 0.0);
  EXPECT_GE(frame.x_max, 10.0);
  EXPECT_LE(frame.y_min, -2.5);
  EXPECT_GE(frame.y_max, 12.0);
  for (const double x : {1.0, 2.5, 6.0, 8.5}) {
    const auto p = frame.pixel(x, 5.0);
    ASSERT_TRUE(p);
    EXPECT_EQ(png.pixel((*p)[0], (*p)[1]), kRed) << "x = " << x;
  }
  EXPECT_TRUE(near(png, frame.pixel(5.0, 6.5), kGreen));  // on the ramp from (3, 1) to (7, 12)
  // Plot area pixels away from the lines are background or grid, never a series colour.
  const auto empty = frame.pixel(9.0, -1.0);
  ASSERT_TRUE(empty);
  EXPECT_NE(png.pixel((*empty)[0], (*empty)[1]), kRed);
  EXPECT_NE(png.pixel((*empty)[0], (*empty)[1]), kGreen);
}

TEST(LinePlotPng, LogAxisSkipsNonPositiveAndNonFiniteValues) {
  LinePlot plot;
  plot.log_y = true;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  plot.series = {{"mixed", kRed, {0, 1, 2, 3, 4, 5}, {1.0, 0.0, -3.0, 10.0, 100.0, nan}}};
  PlotFrame frame;
  const RgbImage image = render_line_plot(plot, &frame);
  EXPECT_TRUE(frame.log_y);
  EXPECT_DOUBLE_EQ(frame.y_min, 0.0);  // log10(1)
  EXPECT_DOUBLE_EQ(frame.y_max, 2.0);  // log10(100)
  EXPECT_FALSE(frame.pixel(1, 0.0));
  EXPECT_FALSE(frame.pixel(2, -3.0));
  EXPECT_FALSE(frame.pixel(5, nan));
  // The isolated point at x = 0 is marked; the segment from (3, 10) to (4, 100) is drawn.
  const auto first = frame.pixel(0, 1.0);
  ASSERT_TRUE(first);
  EXPECT_EQ(image.at((*first)[0] + 1, (*first)[1] - 1), kRed);
  EXPECT_TRUE(near(image, frame.pixel(3.5, std::sqrt(1000.0)), kRed));

  // Only non-positive values: an empty log axis, no crash.
  plot.series = {{"zeros", kRed, {0, 1}, {0.0, -1.0}}};
  EXPECT_NO_THROW(render_line_plot(plot));
}

TEST(LinePlotPng, EmptySeriesAndNoSeriesRender) {
  TempFolder folder("plot_empty");
  LinePlot plot;
  plot.title = "nothing";
  plot.series = {{"empty", kRed, {}, {}}};
  for (const bool log_y : {false, true}) {
    plot.log_y = log_y;
    write_line_plot_png(folder / "empty.png", plot);
    const DecodedPng png = decode(read_bytes(folder / "empty.png"));
    EXPECT_EQ(png.width, 800u);
    EXPECT_EQ(png.pixel(0, 0), kWhite);
  }
  plot.series.clear();
  EXPECT_NO_THROW(render_line_plot(plot));
  plot.series = {{"bad", kRed, {0, 1}, {1}}};
  EXPECT_THROW(render_line_plot(plot), std::invalid_argument);
  plot.series.clear();
  plot.width = 50;
  EXPECT_THROW(render_line_plot(plot), std::invalid_argument);
}

TEST(ConvergencePlot, ObjectiveAndGradientNormOnALogAxis) {
  OptimizerResult result;
  for (int k = 0; k < 5; ++k) {
    OptimizerIteration it;
    it.iteration = k;
    it.objective = std::pow(10.0, -2 * k);
    it.gradient_norm = k == 4 ? 0.0 : std::pow(10.0, -k);
    result.history.push_back(it);
  }
  const LinePlot plot = convergence_plot(result, "test");
  EXPECT_TRUE(plot.log_y);
  ASSERT_EQ(plot.series.size(), 2u);
  EXPECT_EQ(plot.series[0].name, "objective");
  EXPECT_EQ(plot.series[1].name, "gradient norm");
  EXPECT_EQ(plot.series[1].y, (std::vector<double>{1.0, 0.1, 0.01, 0.001, 0.0}));
  PlotFrame frame;
  render_line_plot(plot, &frame);
  EXPECT_DOUBLE_EQ(frame.y_min, -8.0);
  EXPECT_DOUBLE_EQ(frame.y_max, 0.0);

  TempFolder folder("plot_convergence");
  write_convergence_png(folder / "c.png", OptimizerResult{}, "no iterations");  // empty history
  EXPECT_EQ(decode(read_bytes(folder / "c.png")).height, 500u);
}

TEST(ConvergencePlot, TailorRunWritesConvergencePng) {
  TempFolder folder("plot_run");
  const InverseRun run =
      run_inverse_scene(read_scene(kScenes + "/two_material_bar_inverse.json"), folder / "out");
  ASSERT_FALSE(run.result.history.empty());
  const std::string path = folder / "out/convergence.png";
  ASSERT_TRUE(fs::exists(path));
  const DecodedPng png = decode(read_bytes(path));
  EXPECT_EQ(png.width, 800u);
  EXPECT_EQ(png.height, 500u);
  EXPECT_EQ(png.raw.size(), 500u * (1 + 800 * 3));
  EXPECT_EQ(png.pixel(0, 0), kWhite);
}

}  // namespace
}  // namespace tailor
