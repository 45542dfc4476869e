// JSON and plots of a damping study (see damping_study.hpp).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "problems/damping_design/damping_study.hpp"
#include "problems/plot/line_plot.hpp"
#include "problems/report_file.hpp"

namespace tailor {
namespace {

const Rgb kColours[] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {148, 103, 189}, {255, 127, 14}};

// Every k-th record relative to the first, so plots stay light; values below 1e-4 of the first
// (where the Newton tolerance shows, and outside the decay-rate fit) are left out.
LineSeries series(const std::string& name, Rgb colour, const std::vector<double>& t, const Vector& y) {
  LineSeries s{name, colour, {}, {}};
  const std::size_t stride = std::max<std::size_t>(1, t.size() / 600);
  for (std::size_t k = 0; k < t.size(); k += stride) {
    const double relative = y[static_cast<Eigen::Index>(k)] / y[0];
    if (relative < 1e-4) break;
    s.x.push_back(t[k]);
    s.y.push_back(relative);
  }
  return s;
}

Rgb lighter(Rgb c) {
  auto mix = [](std::uint8_t v) { return static_cast<std::uint8_t>((v + 2 * 255) / 3); };
  return {mix(c.r), mix(c.g), mix(c.b)};
}

}  // namespace

std::string write_damping_study(const DampingStudy& study, const std::string& folder) {
  std::filesystem::create_directories(folder);
  nlohmann::json j;
  j["num_dofs"] = study.num_dofs;
  j["num_elements"] = study.num_elements;
  j["time_step"] = study.time_step;
  j["seconds"] = study.seconds;
  for (const ModeDecay& d : study.modes)
    j["modes"].push_back({{"mode", d.mode},
                          {"omega", d.omega},
                          {"gamma", d.gamma},
                          {"rayleigh_rate", d.rayleigh_rate},
                          {"target_rate", d.target_rate},
                          {"designed_rate", d.designed_rate},
                          {"plain_rate", d.plain_rate},
                          {"numerical_rate", d.numerical_rate},
                          {"scheme_factor", d.scheme_factor},
                          {"plain_over_rayleigh", d.plain_rate / d.rayleigh_rate},
                          {"designed_over_target", d.designed_rate / d.target_rate},
                          {"designed_over_plain", d.designed_rate / d.plain_rate},
                          {"numerical_over_target", d.numerical_rate / d.target_rate},
                          {"plain_cycle_loss", d.plain_cycle_loss},
                          {"designed_cycle_loss", d.designed_cycle_loss}});
  j["implicit_euler"] = {{"numerical_rate_mode0", study.implicit_euler_numerical_rate},
                         {"predicted_h_omega2_over_2", study.implicit_euler_predicted_rate}};
  for (const NonlinearCycle& c : study.cycles)
    j["nonlinear_cycles"].push_back({{"amplitude", c.amplitude},
                                     {"mean_amplitude", c.mean_amplitude},
                                     {"achieved_loss", c.achieved_loss},
                                     {"designed_loss", c.designed_loss},
                                     {"achieved_gamma", c.achieved_gamma},
                                     {"designed_gamma", c.designed_gamma}});
  const std::string report_path = write_report(folder, j);

  LinePlot envelope;
  envelope.title =
      "amplitude / initial per mode: achieved, target exp(-gamma sigma_R t) (light), plain Rayleigh (grey)";
  envelope.x_label = "time";
  envelope.y_label = "relative amplitude";
  envelope.log_y = true;
  for (std::size_t k = 0; k < study.modes.size() && k < study.designed.size(); ++k) {
    const VibrationHistory& h = study.designed[k];
    const auto col = static_cast<Eigen::Index>(k);
    const Rgb c = kColours[k % 5];
    envelope.series.push_back(
        series("mode " + std::to_string(k) + " achieved", c, h.time, h.amplitude.col(col)));
    Vector target(h.amplitude.rows());
    for (Eigen::Index r = 0; r < target.size(); ++r)
      target[r] =
          h.amplitude(0, col) * std::exp(-study.modes[k].target_rate * h.time[static_cast<std::size_t>(r)]);
    envelope.series.push_back(series("mode " + std::to_string(k) + " target", lighter(c), h.time, target));
    const VibrationHistory& plain = study.plain[k];
    envelope.series.push_back(series("mode " + std::to_string(k) + " plain Rayleigh", Rgb{120, 120, 120},
                                     plain.time, plain.amplitude.col(col)));
  }
  write_line_plot_png(folder + "/envelope.png", envelope);

  if (!study.cycles.empty()) {
    LinePlot curve;
    curve.title = "damping scale gamma vs amplitude: curve and per-cycle measurement";
    curve.x_label = "amplitude chi";
    curve.y_label = "gamma";
    curve.log_y = false;
    curve.series.push_back({"designed curve", kColours[0], study.curve_amplitude, study.curve_gamma});
    LineSeries achieved{"achieved (per cycle)", kColours[1], {}, {}};
    LineSeries loss{"achieved loss", kColours[1], {}, {}}, designed{"designed loss", kColours[0], {}, {}};
    for (const NonlinearCycle& c : study.cycles) {
      achieved.x.push_back(c.mean_amplitude);
      achieved.y.push_back(c.achieved_gamma);
      loss.x.push_back(c.amplitude);
      loss.y.push_back(c.achieved_loss);
      designed.x.push_back(c.amplitude);
      designed.y.push_back(c.designed_loss);
    }
    curve.series.push_back(achieved);
    write_line_plot_png(folder + "/gamma_curve.png", curve);
    LinePlot cycle;
    cycle.title = "amplitude loss per cycle vs amplitude";
    cycle.x_label = "amplitude chi";
    cycle.y_label = "loss per cycle";
    cycle.log_y = false;
    cycle.series = {designed, loss};
    write_line_plot_png(folder + "/cycle_loss.png", cycle);
  }
  return report_path;
}

}  // namespace tailor
