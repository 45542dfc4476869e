// PNG plots, read back with libpng: round trips of small images, compressed file sizes, known
// pixels of a rendered line plot, log axes with non-positive values, empty series, unwritable
// paths, and DIR/convergence.png of `tailor run`.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "../support/read_png.hpp"
#include "../support/temp_folder.hpp"
#include "problems/fem/inverse_commands.hpp"
#include "problems/plot/convergence_plot.hpp"
#include "problems/plot/line_plot.hpp"
#include "problems/plot/png_writer.hpp"

namespace tailor::plot_test {
namespace {

namespace fs = std::filesystem;
using tailor::testing::read_png;
using tailor::testing::ReadPng;

const std::string kScenes = tailor::testing::kScenesDir;

using TempFolder = tailor::testing::TempFolder;

Rgb image_pixel(const ReadPng& png, int x, int y) { return png.pixel(x, y); }
Rgb image_pixel(const RgbImage& image, int x, int y) { return image.at(x, y); }

// Reads `path`, failing the test when libpng cannot.
ReadPng decode(const std::string& path) {
  ReadPng png = read_png(path);
  EXPECT_EQ(png.error, "") << path;
  EXPECT_EQ(png.colour_type, static_cast<std::uint32_t>(PNG_FORMAT_RGB)) << "8-bit RGB, no alpha";
  EXPECT_EQ(png.rgb.size(), std::size_t{png.width} * png.height * 3);
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

TEST(Png, SmallImageRoundTrips) {
  TempFolder folder("plot_small");
  RgbImage image(3, 2, {10, 20, 30});
  image.set(2, 1, {1, 2, 3});
  image.set(5, 5, {9, 9, 9});  // outside: ignored
  write_png(folder / "small.png", image);
  const ReadPng png = decode(folder / "small.png");
  EXPECT_EQ(png.width, 3u);
  EXPECT_EQ(png.height, 2u);
  EXPECT_EQ(png.pixel(0, 0), (Rgb{10, 20, 30}));
  EXPECT_EQ(png.pixel(1, 1), (Rgb{10, 20, 30}));
  EXPECT_EQ(png.pixel(2, 1), (Rgb{1, 2, 3}));
  EXPECT_THROW(RgbImage(0, 4), std::invalid_argument);
}

// Every pixel survives, in an image with no two neighbours alike (what compresses worst).
TEST(Png, NoisyImageRoundTripsExactly) {
  TempFolder folder("plot_noise");
  RgbImage image(97, 61);
  std::uint32_t state = 12345;
  const auto next = [&state] {
    state = state * 1664525u + 1013904223u;  // a linear congruential generator
    return static_cast<std::uint8_t>(state >> 24);
  };
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) image.set(x, y, {next(), next(), next()});
  write_png(folder / "noise.png", image);
  const ReadPng png = decode(folder / "noise.png");
  ASSERT_EQ(png.width, 97u);
  ASSERT_EQ(png.height, 61u);
  EXPECT_EQ(png.rgb, image.pixels());
}

// A plot is mostly background: compressed, it takes a small fraction of its 1.2 MB of pixels.
TEST(Png, PlotsAreCompressed) {
  LinePlot plot;
  plot.title = "compressed";
  plot.series = {{"ramp", Rgb{200, 0, 0}, {0, 1, 2}, {0, 2, 1}}};
  const RgbImage image = render_line_plot(plot);
  const std::vector<std::uint8_t> file = encode_png(image);
  EXPECT_EQ(image.pixels().size(), 800u * 500u * 3u);
  EXPECT_LT(file.size(), image.pixels().size() / 20) << file.size() << " bytes";
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
  const ReadPng png = decode(folder / "line.png");
  ASSERT_EQ(png.width, 800u);
  ASSERT_EQ(png.height, 500u);
  EXPECT_EQ(png.rgb, image.pixels());  // the file holds exactly the rendered image
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
    const ReadPng png = decode(folder / "empty.png");
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
  EXPECT_EQ(decode(folder / "c.png").height, 500u);
}

TEST(ConvergencePlot, TailorRunWritesConvergencePng) {
  TempFolder folder("plot_run");
  const InverseRun run =
      run_inverse_scene(read_scene(kScenes + "/two_material_bar_inverse.json"), folder / "out");
  ASSERT_FALSE(run.result.history.empty());
  const std::string path = folder / "out/convergence.png";
  ASSERT_TRUE(fs::exists(path));
  const ReadPng png = decode(path);
  EXPECT_EQ(png.width, 800u);
  EXPECT_EQ(png.height, 500u);
  EXPECT_EQ(png.pixel(0, 0), kWhite);
  EXPECT_LT(png.file_size, 200u * 1024u) << "compressed";
}

}  // namespace
}  // namespace tailor::plot_test
