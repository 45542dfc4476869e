#include "problems/damping_design/damping_design_scene.hpp"

#include <cmath>
#include <iomanip>
#include <ostream>

#include "problems/fem/scene.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

DampingStudyOptions parse_damping_design(const SceneNode& top) {
  top.expect_keys({"name", "damping_design"});
  if (const auto name = top.find("name")) name->string();
  const SceneNode d = top.at("damping_design");
  d.expect_keys(
      {"plate", "rayleigh", "examples", "measured_modes", "time_step", "steps", "tip_amplitude", "curve"});
  DampingStudyOptions o;
  if (const auto plate = d.find("plate")) {
    plate->expect_keys(
        {"length", "width", "thickness", "cells", "youngs_modulus", "poisson_ratio", "density"});
    if (const auto v = plate->find("length")) o.plate.length = v->positive();
    if (const auto v = plate->find("width")) o.plate.width = v->positive();
    if (const auto v = plate->find("thickness")) o.plate.thickness = v->positive();
    if (const auto v = plate->find("cells")) {
      const std::vector<int> cells = v->integers(1);
      if (cells.size() != 3) v->fail("expected 3 cell counts (length, width, thickness)");
      o.plate.cells_length = cells[0], o.plate.cells_width = cells[1], o.plate.cells_thickness = cells[2];
    }
    if (const auto v = plate->find("youngs_modulus")) o.plate.youngs_modulus = v->positive();
    if (const auto v = plate->find("poisson_ratio")) o.plate.poisson_ratio = v->open_interval(-1.0, 0.5);
    if (const auto v = plate->find("density")) o.plate.density = v->positive();
  }
  if (const auto r = d.find("rayleigh")) {
    r->expect_keys({"alpha", "beta"});
    o.plate.alpha = r->at("alpha").non_negative();
    o.plate.beta = r->at("beta").non_negative();
  }
  o.plate.example_modes.clear();
  for (const SceneNode& e : d.at("examples").items()) {
    e.expect_keys({"mode", "scale"});
    o.plate.example_modes.push_back(e.at("mode").integer(0));
    o.plate.controls.push_back(Vector::Constant(1, e.at("scale").non_negative()));
  }
  if (o.plate.example_modes.empty()) d.at("examples").fail("at least one example is needed");
  if (const auto v = d.find("measured_modes")) o.plate.measured_modes = v->integer(1);
  for (int mode : o.plate.example_modes)
    if (mode >= o.plate.measured_modes) o.plate.measured_modes = mode + 1;
  if (const auto v = d.find("time_step")) o.vibration.time_step = v->positive();
  if (const auto v = d.find("steps")) o.vibration.steps = v->integer(10);
  if (const auto v = d.find("tip_amplitude")) o.tip_amplitude = v->positive();
  if (const auto c = d.find("curve")) {
    c->expect_keys({"knots", "values", "tip_amplitude", "steps"});
    std::vector<double> knots, values;
    for (const SceneNode& k : c->at("knots").items()) knots.push_back(k.non_negative());
    for (const SceneNode& k : c->at("values").items()) values.push_back(k.non_negative());
    if (knots.size() < 2) c->at("knots").fail("a damping curve needs at least 2 knots");
    if (values.size() != knots.size()) c->at("values").fail("one value per knot is needed");
    for (std::size_t k = 1; k < knots.size(); ++k)
      if (!(knots[k] > knots[k - 1])) c->at("knots").fail("knots must increase");
    o.curve.knots = Eigen::Map<const Vector>(knots.data(), static_cast<Eigen::Index>(knots.size()));
    o.curve_controls = Eigen::Map<const Vector>(values.data(), static_cast<Eigen::Index>(values.size()));
    if (const auto v = c->find("tip_amplitude")) o.nonlinear_tip_amplitude = v->positive();
    if (const auto v = c->find("steps")) o.nonlinear_steps = v->integer(10);
  }
  return o;
}

bool run_damping_design_scene(const SceneNode& root, const std::string& out_dir, std::ostream* log) {
  const DampingStudyOptions options = parse_damping_design(root);
  if (log)
    *log << "damping design study '" << root.source() << "': " << options.plate.example_modes.size()
         << " example(s), " << options.vibration.steps << " steps of h = " << options.vibration.time_step
         << " per mode" << std::endl;
  const DampingStudy s = run_damping_study(options, log);
  const std::string report_path = write_damping_study(s, out_dir);
  bool ok = true;
  if (log) *log << std::setprecision(4);
  for (const ModeDecay& d : s.modes) {
    const bool example = d.gamma != 1.0;
    const double ratio = example ? d.designed_rate / d.target_rate : d.designed_rate / d.plain_rate;
    const bool pass = std::abs(ratio - 1.0) <= 0.05 && std::abs(d.numerical_rate) <= 0.05 * d.target_rate;
    ok = ok && pass;
    if (log)
      *log << "mode " << d.mode << (example ? " (example)" : "") << ": decay rate " << d.designed_rate
           << (example ? " / target " : " / plain Rayleigh ") << ratio << ", numerical damping "
           << d.numerical_rate / d.target_rate << " of the target" << (pass ? "" : "  OUT OF TOLERANCE")
           << "\n";
  }
  if (log) *log << "wrote " << report_path << " and plots\n";
  return ok;
}

}  // namespace tailor
