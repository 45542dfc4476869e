#pragma once
// The damping-design study (Xu & Barbic 2017, "made 10x weaker / made 3x stronger"): a
// cantilever plate whose first two modes are the damping examples, scaled by gamma_1, gamma_2,
// is started in one mode at a time and integrated with the non-dissipative trapezoidal rule;
// the measured decay rate of each mode is compared with its target gamma_k times Rayleigh's
// rate (alpha + beta omega_k^2)/2 (modes that are not examples: Rayleigh's), with plain
// Rayleigh damping (all gamma = 1) run with the same scheme, and with the scheme's own
// numerical damping (alpha = beta = 0). A nonlinear part gives example 1 a damping curve
// gamma(chi) and compares the amplitude lost per cycle with the loss the curve prescribes,
// 1 - chi_end / chi_start for d chi/dt = -gamma(chi) sigma_R chi over the cycle.
#include <iosfwd>
#include <string>
#include <vector>

#include "problems/damping_design/free_vibration.hpp"

namespace tailor {

struct DampingStudyOptions {
  DampingPlateOptions plate;  // plate.controls: the designed constant scales (one value per example)
  VibrationOptions vibration;
  double tip_amplitude = 0.02;  // initial largest displacement [length]
  bool measure_implicit_euler = true;
  // Nonlinear part (skipped when curve has one knot): the curve of example 0, its controls.
  DampingCurve curve;
  Vector curve_controls;
  double nonlinear_tip_amplitude = 0.05;
  int nonlinear_steps = 3000;
};

struct ModeDecay {
  int mode = 0;
  double omega = 0.0;           // [rad / time]
  double gamma = 1.0;           // designed scale (1 for modes that are not examples)
  double rayleigh_rate = 0.0;   // (alpha + beta omega^2) / 2 [1/time]
  double target_rate = 0.0;     // gamma * rayleigh_rate
  double plain_rate = 0.0;      // measured, all gamma = 1
  double designed_rate = 0.0;   // measured, designed gamma
  double numerical_rate = 0.0;  // measured, alpha = beta = 0 (the scheme's own damping)
  // The trapezoidal rule's discrete decay rate of a lightly damped mode is the continuous one
  // times 1 / (1 + (h omega / 2)^2) (from its amplification factor (1 + h l/2)/(1 - h l/2));
  // 1 for other schemes (not predicted).
  double scheme_factor = 1.0;
  double plain_cycle_loss = 0.0, designed_cycle_loss = 0.0;  // 1 - exp(-rate * 2 pi / omega)
};

struct NonlinearCycle {
  double amplitude = 0.0;       // chi at the cycle's start [length]
  double mean_amplitude = 0.0;  // geometric mean of chi at its start and end
  double achieved_loss = 0.0, designed_loss = 0.0;
  double achieved_gamma = 0.0;  // -log(1 - loss) / (sigma_R * period)
  double designed_gamma = 0.0;  // the curve at mean_amplitude
};

struct DampingStudy {
  std::vector<ModeDecay> modes;
  double implicit_euler_numerical_rate = 0.0;     // mode 0, alpha = beta = 0
  double implicit_euler_predicted_rate = 0.0;     // h omega^2 / 2 (small h omega)
  std::vector<VibrationHistory> plain, designed;  // per measured mode
  VibrationHistory nonlinear;
  std::vector<NonlinearCycle> cycles;
  std::vector<double> curve_amplitude, curve_gamma;  // the designed curve, sampled
  int num_dofs = 0, num_elements = 0;
  double time_step = 0.0, seconds = 0.0;
};

DampingStudy run_damping_study(const DampingStudyOptions& options, std::ostream* progress = nullptr);

// `folder`/report.json (problems/report_file.hpp) and the plots envelope.png, gamma_curve.png
// and cycle_loss.png; returns the report's path.
std::string write_damping_study(const DampingStudy& study, const std::string& folder);

}  // namespace tailor
