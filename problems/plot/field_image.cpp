#include "problems/plot/field_image.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "problems/plot/line_plot.hpp"

namespace tailor {
namespace {

constexpr int kMargin = 12;
constexpr int kGap = 6;
constexpr int kTextScale = 2;

using Point = std::array<double, 2>;  // in-plane coordinates (u, v)

// A convex polygon of the picture with its element's value.
struct Polygon {
  std::vector<Point> corners;
  int element = 0;
};

// In-plane axes: the two other than `axis` (2D meshes: x and y).
std::array<int, 2> plane_axes(int dim, int axis) {
  if (dim == 2) return {0, 1};
  std::array<int, 2> out{};
  int k = 0;
  for (int a = 0; a < 3; ++a)
    if (a != axis) out[k++] = a;
  return out;
}

// Triangles as they are; tets cut by the plane (vertices on it count as slightly below, so a
// facet lying in the plane is drawn once, from the tets above it).
std::vector<Polygon> picture_polygons(const Mesh& mesh, const FieldSlice& slice) {
  std::vector<Polygon> out;
  const std::array<int, 2> uv = plane_axes(mesh.dim(), slice.axis);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    Polygon polygon;
    polygon.element = e;
    if (mesh.dim() == 2) {
      for (int k = 0; k < 3; ++k) {
        const int v = mesh.elements(e, k);
        polygon.corners.push_back({mesh.rest_positions(v, 0), mesh.rest_positions(v, 1)});
      }
      out.push_back(std::move(polygon));
      continue;
    }
    std::array<double, 4> d{};
    bool above = false, below = false;
    for (int k = 0; k < 4; ++k) {
      d[k] = mesh.rest_positions(mesh.elements(e, k), slice.axis) - slice.value;
      if (d[k] > 0.0)
        above = true;
      else
        below = true;
    }
    if (!above || !below) continue;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        if ((d[i] > 0.0) == (d[j] > 0.0)) continue;
        const double t = d[i] / (d[i] - d[j]);
        const int a = mesh.elements(e, i), b = mesh.elements(e, j);
        Point p{};
        for (int c = 0; c < 2; ++c)
          p[c] = mesh.rest_positions(a, uv[c]) +
                 t * (mesh.rest_positions(b, uv[c]) - mesh.rest_positions(a, uv[c]));
        polygon.corners.push_back(p);
      }
    // 3 or 4 points of a convex polygon: order them by angle around their mean.
    Point mean{0.0, 0.0};
    for (const Point& p : polygon.corners) {
      mean[0] += p[0] / static_cast<double>(polygon.corners.size());
      mean[1] += p[1] / static_cast<double>(polygon.corners.size());
    }
    std::sort(polygon.corners.begin(), polygon.corners.end(), [&](const Point& p, const Point& q) {
      return std::atan2(p[1] - mean[1], p[0] - mean[0]) < std::atan2(q[1] - mean[1], q[0] - mean[0]);
    });
    out.push_back(std::move(polygon));
  }
  return out;
}

// Fills the triangle (pixel coordinates) where pixel centres lie inside it or on its edges.
void fill_triangle(RgbImage& image, const Point& a, const Point& b, const Point& c, Rgb colour) {
  const double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  if (area == 0.0) return;
  const int x0 = static_cast<int>(std::floor(std::min({a[0], b[0], c[0]})));
  const int x1 = static_cast<int>(std::ceil(std::max({a[0], b[0], c[0]})));
  const int y0 = static_cast<int>(std::floor(std::min({a[1], b[1], c[1]})));
  const int y1 = static_cast<int>(std::ceil(std::max({a[1], b[1], c[1]})));
  const auto edge = [](const Point& p, const Point& q, double x, double y) {
    return (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]);
  };
  const double eps = -1e-9 * std::abs(area);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double w0 = edge(b, c, px, py) * area, w1 = edge(c, a, px, py) * area,
                   w2 = edge(a, b, px, py) * area;
      if (w0 >= eps && w1 >= eps && w2 >= eps) image.set(x, y, colour);
    }
}

std::string format_value(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

}  // namespace

FieldSlice mid_plane(const Mesh& mesh) {
  const Eigen::RowVectorXd lo = mesh.rest_positions.colwise().minCoeff();
  const Eigen::RowVectorXd hi = mesh.rest_positions.colwise().maxCoeff();
  FieldSlice slice;
  slice.axis = mesh.dim() - 1;
  for (int a = mesh.dim() - 1; a >= 0; --a)
    if (hi[a] - lo[a] < hi[slice.axis] - lo[slice.axis]) slice.axis = a;
  slice.value = 0.5 * (lo[slice.axis] + hi[slice.axis]);
  return slice;
}

Rgb field_colour(double t) {
  // Nine samples of a viridis-like scale (dark blue, teal, green, yellow), interpolated.
  static constexpr std::array<std::array<double, 3>, 9> samples{{{68, 1, 84},
                                                                 {71, 44, 122},
                                                                 {59, 82, 139},
                                                                 {44, 113, 142},
                                                                 {33, 145, 140},
                                                                 {39, 173, 129},
                                                                 {92, 200, 99},
                                                                 {170, 220, 50},
                                                                 {253, 231, 37}}};
  t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
  const double s = t * 8.0;
  const int i = std::min(7, static_cast<int>(s));
  const double f = s - i;
  const auto mix = [&](int c) {
    return static_cast<std::uint8_t>(std::lround((1.0 - f) * samples[i][c] + f * samples[i + 1][c]));
  };
  return {mix(0), mix(1), mix(2)};
}

RgbImage render_field_image(const Mesh& mesh, const std::vector<FieldPanel>& panels,
                            const FieldImageOptions& options) {
  if (panels.empty()) throw std::invalid_argument("field image: no panel to draw");
  if (options.panel_width < 80 || options.panel_height < 60)
    throw std::invalid_argument("field image: panels must be at least 80 x 60 pixels");
  double lo = INFINITY, hi = -INFINITY;
  for (const FieldPanel& panel : panels) {
    if (panel.values.size() != mesh.num_elements())
      throw std::invalid_argument("field image: panel '" + panel.title + "' has " +
                                  std::to_string(panel.values.size()) + " values for " +
                                  std::to_string(mesh.num_elements()) + " elements");
    if (!panel.values.allFinite())
      throw std::invalid_argument("field image: panel '" + panel.title + "' has non-finite values");
    lo = std::min(lo, panel.values.minCoeff());
    hi = std::max(hi, panel.values.maxCoeff());
  }
  const double range = hi > lo ? hi - lo : 1.0;

  FieldSlice slice = mid_plane(mesh);
  const std::array<int, 2> uv = plane_axes(mesh.dim(), slice.axis);
  const Eigen::RowVectorXd box_lo = mesh.rest_positions.colwise().minCoeff();
  const Eigen::RowVectorXd box_hi = mesh.rest_positions.colwise().maxCoeff();
  // Off the vertex layers of structured meshes by a hair (see picture_polygons).
  if (mesh.dim() == 3) slice.value += 1e-7 * (box_hi[slice.axis] - box_lo[slice.axis]);
  const std::vector<Polygon> polygons = picture_polygons(mesh, slice);

  const int text_h = text_height(kTextScale);
  const int title_h = options.title.empty() ? 0 : text_h + 2 * kGap;
  const int panel_title_h = text_h + kGap;
  const int bar_w = 24;
  int label_w = 0;
  for (double v : {lo, 0.5 * (lo + hi), hi})
    label_w = std::max(label_w, text_width(format_value(v), kTextScale));
  const int bar_block = kGap + bar_w + kGap + label_w + kMargin;
  const int count = static_cast<int>(panels.size());
  const int width = kMargin + count * (options.panel_width + kGap) + bar_block;
  const int height = kMargin + title_h + panel_title_h + options.panel_height + kMargin +
                     (options.bar_label.empty() && mesh.dim() == 2 ? 0 : text_h + kGap);
  RgbImage image(width, height, {255, 255, 255});
  if (!options.title.empty()) draw_text(image, kMargin, kMargin, options.title, kBlack, kTextScale);

  // World (u, v) -> pixels, aspect ratio kept, v up, centred in the panel.
  const double wu = std::max(box_hi[uv[0]] - box_lo[uv[0]], 1e-300);
  const double wv = std::max(box_hi[uv[1]] - box_lo[uv[1]], 1e-300);
  const double scale =
      std::min((options.panel_width - 2.0 * kGap) / wu, (options.panel_height - 2.0 * kGap) / wv);
  const int top = kMargin + title_h + panel_title_h;
  for (int k = 0; k < count; ++k) {
    const int left = kMargin + k * (options.panel_width + kGap);
    draw_text(image, left, top - panel_title_h, panels[k].title, kBlack, kTextScale);
    const double ox = left + 0.5 * (options.panel_width - scale * wu);
    const double oy = top + 0.5 * (options.panel_height + scale * wv);
    const auto pixel = [&](const Point& p) -> Point {
      return {ox + scale * (p[0] - box_lo[uv[0]]), oy - scale * (p[1] - box_lo[uv[1]])};
    };
    for (const Polygon& polygon : polygons) {
      const Rgb colour = field_colour((panels[k].values[polygon.element] - lo) / range);
      const Point a = pixel(polygon.corners[0]);
      for (std::size_t i = 1; i + 1 < polygon.corners.size(); ++i)
        fill_triangle(image, a, pixel(polygon.corners[i]), pixel(polygon.corners[i + 1]), colour);
    }
  }

  // Colour bar, high values on top, labelled at both ends and the middle.
  const int bar_left = kMargin + count * (options.panel_width + kGap) + kGap;
  const int bar_top = top + text_h / 2, bar_bottom = top + options.panel_height - text_h / 2;
  for (int y = bar_top; y <= bar_bottom; ++y)
    image.fill_rect(bar_left, y, bar_left + bar_w - 1, y,
                    field_colour(static_cast<double>(bar_bottom - y) / std::max(1, bar_bottom - bar_top)));
  const std::array<std::pair<double, int>, 3> labels{
      {{hi, bar_top}, {0.5 * (lo + hi), (bar_top + bar_bottom) / 2}, {lo, bar_bottom}}};
  for (const auto& [value, y] : labels) {
    image.fill_rect(bar_left + bar_w, y, bar_left + bar_w + 3, y, kBlack);
    draw_text(image, bar_left + bar_w + kGap, y - text_h / 2, format_value(value), kBlack, kTextScale);
  }
  std::string caption = options.bar_label;
  if (mesh.dim() == 3)
    caption += std::string(caption.empty() ? "" : ", ") + "slice " +
               std::string(1, static_cast<char>('x' + slice.axis)) + " = " + format_value(slice.value);
  if (!caption.empty()) draw_text(image, kMargin, height - kMargin - text_h, caption, kBlack, kTextScale);
  return image;
}

void write_field_png(const std::string& path, const Mesh& mesh, const std::vector<FieldPanel>& panels,
                     const FieldImageOptions& options) {
  write_png(path, render_field_image(mesh, panels, options));
}

}  // namespace tailor
