#pragma once
// Free vibration of a damping plate and what is measured from it: modal coordinates and
// amplitudes over time, decay rates (least-squares slope of log amplitude) and the amplitude
// lost per oscillation cycle.
#include <vector>

#include "forward/dynamics/time_integrator.hpp"
#include "problems/damping_design/damping_plate.hpp"

namespace tailor {

struct VibrationOptions {
  TimeScheme scheme = TimeScheme::newmark;
  double time_step = 4e-3;  // [time]
  int steps = 1000;
};

struct VibrationHistory {
  std::vector<double> time;  // records: t = 0 and after every step
  Matrix coordinate;         // q_k = phi_k^T M (x - X) of each measured mode (records x modes)
  Matrix amplitude;          // sqrt(q_k^2 + (qdot_k / omega_k)^2): constant for an undamped mode
  Matrix example_amplitude;  // the damping term's chi_i(x, v) [length] (records x examples)
  int newton_iterations = 0;
  double seconds = 0.0;
};

// Throws std::runtime_error naming the step when Newton fails.
VibrationHistory simulate_vibration(DampingPlate& plate, const Vector& p, const Vector& x0, const Vector& v0,
                                    const VibrationOptions& options);

// -d log(a)/dt by least squares over records with time in [t_begin, t_end] and amplitude above
// relative_floor times the first record's (below it, the Newton tolerance's error dominates) [1/time].
double decay_rate(const std::vector<double>& time, const Vector& amplitude, double t_begin = 0.0,
                  double t_end = 1e300, double relative_floor = 1e-4);

struct CycleLoss {
  double time = 0.0;       // start of the cycle
  double period = 0.0;     // its duration
  double amplitude = 0.0;  // amplitude at its start
  double loss = 0.0;       // 1 - amplitude at its end / amplitude at its start
};
// Cycles between successive upward zero crossings of `coordinate` (linear interpolation of
// the crossing times and of the amplitude there).
std::vector<CycleLoss> cycle_losses(const std::vector<double>& time, const Vector& coordinate,
                                    const Vector& amplitude);

}  // namespace tailor
