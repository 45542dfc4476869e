#include "problems/damping_design/damping_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <ostream>
#include <stdexcept>

namespace tailor {
namespace {

// Initial state: the plate displaced along mode k with the given largest displacement.
Vector displaced(const DampingPlate& plate, int k, double tip_amplitude) {
  const Vector phi = plate.modes.col(k);
  return plate.rest + (tip_amplitude / phi.cwiseAbs().maxCoeff()) * phi;
}

double cycle_loss(double rate, double omega) {
  return 1.0 - std::exp(-rate * 2.0 * std::numbers::pi / omega);
}

// 1 - chi(T)/chi(0) for d chi/dt = -gamma(chi) sigma chi (classical RK4).
double designed_loss(const DampingPlate& plate, int example, const Vector& p, double sigma, double chi0,
                     double period) {
  const int n = 200;
  const double h = period / n;
  auto f = [&](double chi) { return -plate.term().curve(example, p, chi) * sigma * chi; };
  double chi = chi0;
  for (int k = 0; k < n; ++k) {
    const double k1 = f(chi), k2 = f(chi + 0.5 * h * k1), k3 = f(chi + 0.5 * h * k2), k4 = f(chi + h * k3);
    chi += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return 1.0 - chi / chi0;
}

}  // namespace

DampingStudy run_damping_study(const DampingStudyOptions& o, std::ostream* progress) {
  const auto t0 = std::chrono::steady_clock::now();
  DampingStudy study;
  DampingPlateOptions plate_options = o.plate;
  const std::vector<Vector> designed_controls = plate_options.controls;
  plate_options.controls.clear();
  plate_options.curves.clear();
  DampingPlate plate = make_damping_plate(plate_options);
  study.num_dofs = plate.model->num_dofs();
  study.num_elements = plate.mesh.num_elements();
  study.time_step = o.vibration.time_step;
  const Vector plain = plate.p;
  Vector designed = plate.p;
  for (std::size_t i = 0; i < designed_controls.size(); ++i) {
    if (designed_controls[i].size() != 1)
      throw std::invalid_argument("damping study: example " + std::to_string(i) +
                                  " needs one designed scale");
    designed.segment(plate.damping.curve_offset + plate.term().curve_begin(static_cast<int>(i)), 1) =
        designed_controls[i];
  }
  Vector undamped = plate.p;
  undamped[plate.damping.alpha_offset] = undamped[plate.damping.beta_offset] = 0.0;
  const Vector v0 = Vector::Zero(plate.rest.size());

  for (int k = 0; k < plate.modes.cols(); ++k) {
    ModeDecay d;
    d.mode = k;
    d.omega = plate.omega[k];
    for (std::size_t i = 0; i < plate_options.example_modes.size(); ++i)
      if (plate_options.example_modes[i] == k && i < designed_controls.size())
        d.gamma = designed_controls[i][0];
    d.rayleigh_rate = plate.rayleigh_decay_rate(k);
    d.target_rate = d.gamma * d.rayleigh_rate;
    if (o.vibration.scheme == TimeScheme::newmark) {
      const double half = 0.5 * o.vibration.time_step * d.omega;
      d.scheme_factor = 1.0 / (1.0 + half * half);
    }
    const Vector x0 = displaced(plate, k, o.tip_amplitude);
    study.plain.push_back(simulate_vibration(plate, plain, x0, v0, o.vibration));
    study.designed.push_back(simulate_vibration(plate, designed, x0, v0, o.vibration));
    VibrationOptions short_run = o.vibration;  // the scheme's own damping is tiny: fewer steps suffice
    short_run.steps = std::max(1, o.vibration.steps / 2);
    const VibrationHistory numerical = simulate_vibration(plate, undamped, x0, v0, short_run);
    d.plain_rate = decay_rate(study.plain.back().time, study.plain.back().amplitude.col(k));
    d.designed_rate = decay_rate(study.designed.back().time, study.designed.back().amplitude.col(k));
    d.numerical_rate = decay_rate(numerical.time, numerical.amplitude.col(k));
    d.plain_cycle_loss = cycle_loss(d.plain_rate, d.omega);
    d.designed_cycle_loss = cycle_loss(d.designed_rate, d.omega);
    study.modes.push_back(d);
    if (progress)
      *progress << "mode " << k << ": omega " << d.omega << ", gamma " << d.gamma << ", target rate "
                << d.target_rate << ", designed " << d.designed_rate << ", plain " << d.plain_rate
                << ", numerical " << d.numerical_rate << std::endl;
  }
  if (o.measure_implicit_euler) {
    VibrationOptions ie = o.vibration;
    ie.scheme = TimeScheme::implicit_euler;
    ie.steps = std::min(ie.steps, 400);
    const VibrationHistory h =
        simulate_vibration(plate, undamped, displaced(plate, 0, o.tip_amplitude), v0, ie);
    study.implicit_euler_numerical_rate = decay_rate(h.time, h.amplitude.col(0));
    study.implicit_euler_predicted_rate = 0.5 * ie.time_step * plate.omega[0] * plate.omega[0];
  }

  if (o.curve.knots.size() > 1) {
    DampingPlateOptions nl = plate_options;
    nl.curves = std::vector<DampingCurve>(plate_options.example_modes.size());
    nl.curves[0] = o.curve;
    DampingPlate curved = make_damping_plate(nl);
    curved.set_controls(0, o.curve_controls);
    VibrationOptions v = o.vibration;
    v.steps = o.nonlinear_steps;
    study.nonlinear =
        simulate_vibration(curved, curved.p, displaced(curved, 0, o.nonlinear_tip_amplitude), v0, v);
    const double sigma = curved.rayleigh_decay_rate(0);
    const std::vector<CycleLoss> cycles = cycle_losses(
        study.nonlinear.time, study.nonlinear.coordinate.col(0), study.nonlinear.example_amplitude.col(0));
    for (const CycleLoss& c : cycles) {
      NonlinearCycle n;
      n.amplitude = c.amplitude;
      n.achieved_loss = c.loss;
      n.designed_loss = designed_loss(curved, 0, curved.p, sigma, c.amplitude, c.period);
      n.achieved_gamma = -std::log(1.0 - c.loss) / (sigma * c.period);
      n.mean_amplitude = c.amplitude * std::sqrt(1.0 - c.loss);
      n.designed_gamma = curved.term().curve(0, curved.p, n.mean_amplitude);
      study.cycles.push_back(n);
    }
    const double top = o.curve.knots[o.curve.knots.size() - 1] * 1.2;
    for (int k = 0; k <= 200; ++k) {
      study.curve_amplitude.push_back(top * k / 200.0);
      study.curve_gamma.push_back(curved.term().curve(0, curved.p, top * k / 200.0));
    }
    if (progress) *progress << "nonlinear: " << study.cycles.size() << " cycles measured" << std::endl;
  }
  study.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return study;
}

}  // namespace tailor
