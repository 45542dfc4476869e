#pragma once
// Line plots rendered into an RgbImage: several named, coloured (x, y) series, a linear x axis,
// a linear or log10 y axis, tick marks with numeric labels, light grid lines, a title, axis
// labels and a legend. Text uses a built-in 5x7 bitmap font (scaled up; no anti-aliasing).
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "problems/plot/png_writer.hpp"

namespace tailor {

struct LineSeries {
  std::string name;  // shown in the legend
  Rgb colour;
  std::vector<double> x, y;  // same length; non-finite points (and y <= 0 on a log axis) are skipped
};

struct LinePlot {
  std::string title, x_label, y_label;
  bool log_y = false;
  int width = 800, height = 500;  // pixels
  std::vector<LineSeries> series;
};

// Where the data went: the plot area in pixels and the axis ranges (log10 y when log_y).
struct PlotFrame {
  int left = 0, top = 0, right = 0, bottom = 0;  // inclusive pixel bounds of the plot area
  double x_min = 0.0, x_max = 1.0, y_min = 0.0, y_max = 1.0;
  bool log_y = false;
  // The pixel of data point (x, y); nullopt when it cannot be drawn (non-finite, y <= 0 on a log axis).
  std::optional<std::array<int, 2>> pixel(double x, double y) const;
};

// Throws std::invalid_argument for a series whose x and y differ in length, or a size too
// small for the axes (under 200 x 150).
RgbImage render_line_plot(const LinePlot& plot, PlotFrame* frame = nullptr);
// render_line_plot + write_png; throws std::runtime_error naming the path when it cannot write.
void write_line_plot_png(const std::string& path, const LinePlot& plot);

// The bitmap font: text drawn with its top-left corner at (x, y), each font pixel a
// scale x scale square. Characters without a glyph show as '?'.
void draw_text(RgbImage& image, int x, int y, const std::string& text, Rgb colour, int scale = 1);
int text_width(const std::string& text, int scale = 1);
int text_height(int scale = 1);

}  // namespace tailor
