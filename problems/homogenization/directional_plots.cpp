#include "problems/homogenization/directional_plots.hpp"

#include <algorithm>
#include <cmath>

#include "problems/plot/line_plot.hpp"

namespace tailor {

void write_directional_plots(const std::string& out_dir, const std::string& title,
                             const std::vector<DirectionalSamples>& samples) {
  const Rgb colours[3] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}};
  LinePlot polar;
  polar.title = title + ": Young's modulus E(d)";
  polar.x_label = "E cos(theta)";
  polar.y_label = "E sin(theta)";
  polar.width = 900;  // the legend takes about 200 pixels: keep the plot area near square
  polar.height = 700;
  LinePlot poisson;
  poisson.title = title + ": Poisson's ratio nu(d, n)";
  poisson.x_label = "angle of d (degrees)";
  poisson.y_label = "nu";
  double max_modulus = 0.0;
  for (std::size_t p = 0; p < samples.size(); ++p) {
    const DirectionalSamples& s = samples[p];
    LineSeries curve{"E(d) in " + s.plane, colours[p % 3], {}, {}};
    LineSeries ratio{"nu in " + s.plane, colours[p % 3], {}, {}};
    for (std::size_t k = 0; k < s.angle.size(); ++k) {
      curve.x.push_back(s.youngs_modulus[k] * std::cos(s.angle[k]));
      curve.y.push_back(s.youngs_modulus[k] * std::sin(s.angle[k]));
      ratio.x.push_back(s.angle[k] * 180.0 / M_PI);
      ratio.y.push_back(s.poisson_ratio[k]);
      max_modulus = std::max(max_modulus, s.youngs_modulus[k]);
    }
    polar.series.push_back(std::move(curve));
    poisson.series.push_back(std::move(ratio));
  }
  LineSeries circle{"max E", {180, 180, 180}, {}, {}};
  for (int k = 0; k <= 180; ++k) {
    circle.x.push_back(max_modulus * std::cos(2.0 * M_PI * k / 180));
    circle.y.push_back(max_modulus * std::sin(2.0 * M_PI * k / 180));
  }
  polar.series.insert(polar.series.begin(), std::move(circle));
  write_line_plot_png(out_dir + "/youngs_modulus_polar.png", polar);
  write_line_plot_png(out_dir + "/poisson_ratio.png", poisson);
}

}  // namespace tailor
