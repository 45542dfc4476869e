#include "problems/plot/line_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace tailor {
namespace {

// 5x7 glyphs, one byte per row from the top, bit 4 the leftmost column; letters with a
// descender (g, j, p, q, y) are drawn `drop` rows lower, below the baseline.
struct Glyph {
  char c;
  std::uint8_t rows[7];
  int drop = 0;
};

constexpr Glyph kFont[] = {
    {' ', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}},
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'A', {0x0E, 0x11, 0x11, 0x11, 0x1F, 0x11, 0x11}},
    {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}},
    {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
    {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
    {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}},
    {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}},
    {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}},
    {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
    {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}},
    {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}},
    {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {'a', {0x00, 0x00, 0x0E, 0x01, 0x0F, 0x11, 0x0F}},
    {'b', {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x1E}},
    {'c', {0x00, 0x00, 0x0E, 0x10, 0x10, 0x11, 0x0E}},
    {'d', {0x01, 0x01, 0x0D, 0x13, 0x11, 0x11, 0x0F}},
    {'e', {0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E}},
    {'f', {0x06, 0x09, 0x08, 0x1C, 0x08, 0x08, 0x08}},
    {'g', {0x0F, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x0E}, 2},
    {'h', {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x11}},
    {'i', {0x04, 0x00, 0x0C, 0x04, 0x04, 0x04, 0x0E}},
    {'j', {0x02, 0x00, 0x06, 0x02, 0x02, 0x12, 0x0C}, 1},
    {'k', {0x10, 0x10, 0x12, 0x14, 0x18, 0x14, 0x12}},
    {'l', {0x0C, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'m', {0x00, 0x00, 0x1A, 0x15, 0x15, 0x11, 0x11}},
    {'n', {0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11}},
    {'o', {0x00, 0x00, 0x0E, 0x11, 0x11, 0x11, 0x0E}},
    {'p', {0x1E, 0x11, 0x11, 0x11, 0x1E, 0x10, 0x10}, 2},
    {'q', {0x0F, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x01}, 2},
    {'r', {0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10}},
    {'s', {0x00, 0x00, 0x0E, 0x10, 0x0E, 0x01, 0x1E}},
    {'t', {0x08, 0x08, 0x1C, 0x08, 0x08, 0x09, 0x06}},
    {'u', {0x00, 0x00, 0x11, 0x11, 0x11, 0x13, 0x0D}},
    {'v', {0x00, 0x00, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'w', {0x00, 0x00, 0x11, 0x11, 0x15, 0x15, 0x0A}},
    {'x', {0x00, 0x00, 0x11, 0x0A, 0x04, 0x0A, 0x11}},
    {'y', {0x11, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x0E}, 2},
    {'z', {0x00, 0x00, 0x1F, 0x02, 0x04, 0x08, 0x1F}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {',', {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}},
    {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
    {'=', {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
    {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'[', {0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E}},
    {']', {0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E}},
    {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
    {'|', {0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}},
    {'\'', {0x0C, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00}},
    {'*', {0x00, 0x04, 0x15, 0x0E, 0x15, 0x04, 0x00}},
    {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
    {'?', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04}},
};

const Glyph& glyph(char c) {
  for (const Glyph& g : kFont)
    if (g.c == c) return g;
  for (const Glyph& g : kFont)
    if (g.c == '?') return g;
  return kFont[0];
}

constexpr Rgb kGrid{225, 225, 225};
constexpr Rgb kTickText{40, 40, 40};

// A "nice" step (1, 2 or 5 times a power of ten) giving about `target` intervals over `range`.
double nice_step(double range, int target) {
  const double raw = range / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / magnitude;
  return (f < 1.5 ? 1.0 : f < 3.0 ? 2.0 : f < 7.0 ? 5.0 : 10.0) * magnitude;
}

std::string format_tick(double v, double step) {
  if (std::abs(v) < step * 1e-9) v = 0.0;
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

struct Tick {
  double value;  // axis units (log10 y on a log axis)
  std::string label;
};

// Linear axis over [lo, hi] widened to whole steps; fills the ticks.
void linear_axis(double& lo, double& hi, bool integer_steps, std::vector<Tick>& ticks) {
  if (!(hi > lo)) {
    const double pad = lo == 0.0 ? 1.0 : std::abs(lo) * 0.1;
    lo -= pad;
    hi += pad;
  }
  double step = nice_step(hi - lo, 6);
  if (integer_steps) step = std::max(step, 1.0);
  lo = std::floor(lo / step + 1e-9) * step;
  hi = std::ceil(hi / step - 1e-9) * step;
  const long n = std::lround((hi - lo) / step);
  for (long i = 0; i <= n; ++i) {
    const double v = lo + static_cast<double>(i) * step;
    ticks.push_back({v, format_tick(v, step)});
  }
}

// Log axis over [lo, hi] in log10 units widened to whole decades; ticks at 1eN.
void log_axis(double& lo, double& hi, std::vector<Tick>& ticks) {
  lo = std::floor(lo + 1e-9);
  hi = std::ceil(hi - 1e-9);
  if (!(hi > lo)) hi = lo + 1.0;
  const int decades = static_cast<int>(hi - lo);
  const int every = (decades + 7) / 8;  // at most about 8 labelled decades
  for (int d = 0; d <= decades; d += every) {
    const int e = static_cast<int>(lo) + d;
    ticks.push_back({static_cast<double>(e), "1e" + std::to_string(e)});
  }
}

bool drawable(double x, double y, bool log_y) {
  return std::isfinite(x) && std::isfinite(y) && (!log_y || y > 0.0);
}

// Bresenham line, 2 pixels thick, clipped to the rectangle [x0c, x1c] x [y0c, y1c].
void draw_line(RgbImage& image, int xa, int ya, int xb, int yb, Rgb colour, int x0c, int y0c, int x1c,
               int y1c) {
  auto plot = [&](int x, int y) {
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx)
        if (x + dx >= x0c && x + dx <= x1c && y + dy >= y0c && y + dy <= y1c)
          image.set(x + dx, y + dy, colour);
  };
  const int dx = std::abs(xb - xa), sx = xa < xb ? 1 : -1;
  const int dy = -std::abs(yb - ya), sy = ya < yb ? 1 : -1;
  int err = dx + dy;
  for (;;) {
    plot(xa, ya);
    if (xa == xb && ya == yb) break;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      xa += sx;
    }
    if (e2 <= dx) {
      err += dx;
      ya += sy;
    }
  }
}

}  // namespace

int text_width(const std::string& text, int scale) {
  return text.empty() ? 0 : static_cast<int>(text.size()) * 6 * scale - scale;
}

int text_height(int scale) { return 7 * scale; }

void draw_text(RgbImage& image, int x, int y, const std::string& text, Rgb colour, int scale) {
  for (const char c : text) {
    const Glyph& g = glyph(c);
    for (int row = 0; row < 7; ++row)
      for (int col = 0; col < 5; ++col)
        if (g.rows[row] & (0x10 >> col))
          image.fill_rect(x + col * scale, y + (row + g.drop) * scale, x + (col + 1) * scale - 1,
                          y + (row + g.drop + 1) * scale - 1, colour);
    x += 6 * scale;
  }
}

std::optional<std::array<int, 2>> PlotFrame::pixel(double x, double y) const {
  if (!drawable(x, y, log_y)) return std::nullopt;
  const double v = log_y ? std::log10(y) : y;
  const double fx = (x - x_min) / (x_max - x_min);
  const double fy = (v - y_min) / (y_max - y_min);
  return std::array<int, 2>{left + static_cast<int>(std::lround(fx * (right - left))),
                            bottom - static_cast<int>(std::lround(fy * (bottom - top)))};
}

RgbImage render_line_plot(const LinePlot& plot, PlotFrame* frame_out) {
  if (plot.width < 200 || plot.height < 150)
    throw std::invalid_argument("line plot: " + std::to_string(plot.width) + " x " +
                                std::to_string(plot.height) + " pixels is too small (at least 200 x 150)");
  for (const LineSeries& s : plot.series)
    if (s.x.size() != s.y.size())
      throw std::invalid_argument("line plot: series '" + s.name + "' has " + std::to_string(s.x.size()) +
                                  " x values but " + std::to_string(s.y.size()) + " y values");

  // Data ranges over the drawable points.
  PlotFrame f;
  f.log_y = plot.log_y;
  bool any = false, integer_x = true;
  double x_lo = 0, x_hi = 0, y_lo = 0, y_hi = 0;
  for (const LineSeries& s : plot.series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!drawable(s.x[i], s.y[i], plot.log_y)) continue;
      const double v = plot.log_y ? std::log10(s.y[i]) : s.y[i];
      if (!any) {
        x_lo = x_hi = s.x[i];
        y_lo = y_hi = v;
        any = true;
      }
      x_lo = std::min(x_lo, s.x[i]);
      x_hi = std::max(x_hi, s.x[i]);
      y_lo = std::min(y_lo, v);
      y_hi = std::max(y_hi, v);
      integer_x = integer_x && s.x[i] == std::round(s.x[i]);
    }
  if (!any) {
    x_lo = 0.0;
    x_hi = 1.0;
    y_lo = 0.0;
    y_hi = 1.0;
  }
  std::vector<Tick> x_ticks, y_ticks;
  linear_axis(x_lo, x_hi, integer_x, x_ticks);
  if (plot.log_y)
    log_axis(y_lo, y_hi, y_ticks);
  else
    linear_axis(y_lo, y_hi, false, y_ticks);
  f.x_min = x_lo;
  f.x_max = x_hi;
  f.y_min = y_lo;
  f.y_max = y_hi;

  // Layout.
  const int s = 2;  // scale of labels and legend
  int title_s = 3;  // scale of the title, smaller when it would not fit
  while (title_s > 1 && text_width(plot.title, title_s) > plot.width - 2 * 12) --title_s;
  const int tick_len = 6, gap = 6, margin = 12;
  int y_label_width = 0;
  for (const Tick& t : y_ticks) y_label_width = std::max(y_label_width, text_width(t.label, s));
  int legend_width = 0;
  for (const LineSeries& ser : plot.series) legend_width = std::max(legend_width, text_width(ser.name, s));
  const int sample = 28;  // the legend's line sample
  if (!plot.series.empty()) legend_width += sample + 3 * gap + 2 * gap;

  f.left = margin + y_label_width + gap + tick_len;
  f.top = margin + (plot.title.empty() ? 0 : text_height(title_s) + 2 * gap) +
          (plot.y_label.empty() ? 0 : text_height(s) + 2 * gap) + text_height(s) / 2 + gap;
  f.right = plot.width - 1 - margin - (legend_width > 0 ? legend_width + 2 * gap : 0);
  f.bottom = plot.height - 1 - margin - (plot.x_label.empty() ? 0 : text_height(s) + gap) - text_height(s) -
             gap - tick_len;
  if (f.right - f.left < 40 || f.bottom - f.top < 40)
    throw std::invalid_argument("line plot: " + std::to_string(plot.width) + " x " +
                                std::to_string(plot.height) +
                                " pixels leave no room for the data (long legend names?)");

  RgbImage image(plot.width, plot.height, {255, 255, 255});

  // Grid lines and ticks.
  std::vector<std::pair<int, const Tick*>> x_at, y_at;
  for (const Tick& t : x_ticks) {
    const int px = f.left + static_cast<int>(
                                std::lround((t.value - f.x_min) / (f.x_max - f.x_min) * (f.right - f.left)));
    x_at.emplace_back(px, &t);
    image.fill_rect(px, f.top, px, f.bottom, kGrid);
  }
  for (const Tick& t : y_ticks) {
    const int py =
        f.bottom -
        static_cast<int>(std::lround((t.value - f.y_min) / (f.y_max - f.y_min) * (f.bottom - f.top)));
    y_at.emplace_back(py, &t);
    image.fill_rect(f.left, py, f.right, py, kGrid);
  }

  // Series.
  for (const LineSeries& ser : plot.series) {
    std::optional<std::array<int, 2>> previous;
    const std::size_t n = ser.x.size();
    for (std::size_t i = 0; i < n; ++i) {
      const auto p = f.pixel(ser.x[i], ser.y[i]);
      if (p && previous)
        draw_line(image, (*previous)[0], (*previous)[1], (*p)[0], (*p)[1], ser.colour, f.left, f.top, f.right,
                  f.bottom);
      // A point with no drawable neighbour gets a small square so that it shows.
      const bool before = i > 0 && drawable(ser.x[i - 1], ser.y[i - 1], plot.log_y);
      const bool after = i + 1 < n && drawable(ser.x[i + 1], ser.y[i + 1], plot.log_y);
      if (p && !before && !after)
        image.fill_rect(std::max((*p)[0] - 2, f.left), std::max((*p)[1] - 2, f.top),
                        std::min((*p)[0] + 2, f.right), std::min((*p)[1] + 2, f.bottom), ser.colour);
      previous = p;
    }
  }

  // Frame, tick marks and tick labels.
  image.fill_rect(f.left, f.top, f.right, f.top, kBlack);
  image.fill_rect(f.left, f.bottom, f.right, f.bottom, kBlack);
  image.fill_rect(f.left, f.top, f.left, f.bottom, kBlack);
  image.fill_rect(f.right, f.top, f.right, f.bottom, kBlack);
  for (const auto& [px, t] : x_at) {
    image.fill_rect(px, f.bottom + 1, px, f.bottom + tick_len, kBlack);
    draw_text(image, px - text_width(t->label, s) / 2, f.bottom + tick_len + gap, t->label, kTickText, s);
  }
  for (const auto& [py, t] : y_at) {
    image.fill_rect(f.left - tick_len, py, f.left - 1, py, kBlack);
    draw_text(image, f.left - tick_len - gap - text_width(t->label, s), py - text_height(s) / 2, t->label,
              kTickText, s);
  }

  // Title, axis labels (the y label sits above the axis, unrotated) and legend.
  if (!plot.title.empty())
    draw_text(image, (plot.width - text_width(plot.title, title_s)) / 2, margin, plot.title, kBlack, title_s);
  if (!plot.y_label.empty())
    draw_text(image, std::max(margin, f.left - text_width(plot.y_label, s) / 2),
              f.top - text_height(s) / 2 - 2 * gap - text_height(s), plot.y_label, kBlack, s);
  if (!plot.x_label.empty())
    draw_text(image, (f.left + f.right - text_width(plot.x_label, s)) / 2,
              plot.height - 1 - margin - text_height(s), plot.x_label, kBlack, s);
  if (!plot.series.empty()) {
    const int row = text_height(s) + 2 * gap;
    const int x0 = f.right + 2 * gap, y0 = f.top;
    const int x1 = x0 + legend_width, y1 = y0 + static_cast<int>(plot.series.size()) * row + gap;
    image.fill_rect(x0, y0, x1, y0, kBlack);
    image.fill_rect(x0, y1, x1, y1, kBlack);
    image.fill_rect(x0, y0, x0, y1, kBlack);
    image.fill_rect(x1, y0, x1, y1, kBlack);
    for (std::size_t i = 0; i < plot.series.size(); ++i) {
      const int ty = y0 + gap + static_cast<int>(i) * row + gap;
      const int mid = ty + text_height(s) / 2;
      image.fill_rect(x0 + gap, mid - 1, x0 + gap + sample, mid, plot.series[i].colour);
      draw_text(image, x0 + 2 * gap + sample + gap, ty, plot.series[i].name, kBlack, s);
    }
  }
  if (frame_out) *frame_out = f;
  return image;
}

void write_line_plot_png(const std::string& path, const LinePlot& plot) {
  write_png(path, render_line_plot(plot));
}

}  // namespace tailor
