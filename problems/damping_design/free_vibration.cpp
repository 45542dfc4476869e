#include "problems/damping_design/free_vibration.hpp"

#include <chrono>
#include <stdexcept>

namespace tailor {

VibrationHistory simulate_vibration(DampingPlate& plate, const Vector& p, const Vector& x0, const Vector& v0,
                                    const VibrationOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  TimeIntegratorOptions o;
  o.scheme = options.scheme;
  o.time_step = options.time_step;
  TimeIntegrator integrator(*plate.model, o);
  DynamicState state = integrator.initial_state(x0, v0, p);
  const Eigen::Index modes = plate.modes.cols(), examples = plate.term().num_examples();
  VibrationHistory h;
  h.coordinate.resize(options.steps + 1, modes);
  h.amplitude.resize(options.steps + 1, modes);
  h.example_amplitude.resize(options.steps + 1, examples);
  const Matrix W = plate.mass * plate.modes;
  auto record = [&](int k) {
    h.time.push_back(state.time);
    const Vector q = W.transpose() * (state.x - plate.rest), qd = W.transpose() * state.v;
    for (Eigen::Index j = 0; j < modes; ++j) {
      h.coordinate(k, j) = q[j];
      h.amplitude(k, j) = std::hypot(q[j], qd[j] / plate.omega[j]);
    }
    for (Eigen::Index i = 0; i < examples; ++i)
      h.example_amplitude(k, i) = plate.term().amplitude(static_cast<int>(i), state.x, state.v);
  };
  record(0);
  for (int k = 1; k <= options.steps; ++k) {
    const NewtonResult r = integrator.step(state, p);
    if (!r.converged())
      throw std::runtime_error("free vibration: step " + std::to_string(k) + " failed: " + r.message);
    h.newton_iterations += r.iterations;
    record(k);
  }
  h.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return h;
}

double decay_rate(const std::vector<double>& time, const Vector& amplitude, double t_begin, double t_end,
                  double relative_floor) {
  double n = 0, st = 0, sy = 0, stt = 0, sty = 0;
  const double floor = amplitude.size() > 0 ? relative_floor * amplitude[0] : 0.0;
  for (std::size_t k = 0; k < time.size(); ++k) {
    const double t = time[k], a = amplitude[static_cast<Eigen::Index>(k)];
    if (t < t_begin || t > t_end || !(a > floor) || !(a > 0.0)) continue;
    const double y = std::log(a);
    n += 1, st += t, sy += y, stt += t * t, sty += t * y;
  }
  if (n < 2)
    throw std::invalid_argument(
        "a decay rate needs at least two amplitude records above " + std::to_string(relative_floor) +
        " of the first in its fitting window; the free vibration has " + std::to_string(static_cast<int>(n)) +
        " (take more time steps, or a shorter time step)");
  return -(n * sty - st * sy) / (n * stt - st * st);
}

std::vector<CycleLoss> cycle_losses(const std::vector<double>& time, const Vector& coordinate,
                                    const Vector& amplitude) {
  struct Crossing {
    double time, amplitude;
  };
  std::vector<Crossing> crossings;
  for (std::size_t k = 1; k < time.size(); ++k) {
    const auto a = static_cast<Eigen::Index>(k - 1), b = static_cast<Eigen::Index>(k);
    if (coordinate[a] < 0.0 && coordinate[b] >= 0.0) {
      const double s = -coordinate[a] / (coordinate[b] - coordinate[a]);
      crossings.push_back(
          {time[k - 1] + s * (time[k] - time[k - 1]), amplitude[a] + s * (amplitude[b] - amplitude[a])});
    }
  }
  std::vector<CycleLoss> cycles;
  for (std::size_t c = 1; c < crossings.size(); ++c)
    cycles.push_back({crossings[c - 1].time, crossings[c].time - crossings[c - 1].time,
                      crossings[c - 1].amplitude, 1.0 - crossings[c].amplitude / crossings[c - 1].amplitude});
  return cycles;
}

}  // namespace tailor
