// Fast version of bench/damping_design_bench: on a coarse cantilever plate whose first two
// modes are the damping examples, example 0 made 10x weaker and example 1 3x stronger
// (Xu & Barbic 2017), the measured decay rates of those modes match gamma times Rayleigh's
// closed-form modal decay rate (alpha + beta omega^2)/2 within 5%, a third mode keeps plain
// Rayleigh's within 5%, and the trapezoidal rule's own damping is below 5% of every target
// (implicit Euler's is h omega^2 / 2, the textbook value, for contrast); plain Rayleigh matches
// the closed-form rate times the trapezoidal rule's factor 1/(1 + (h omega/2)^2). A rising damping
// curve on example 0 makes the measured loss per cycle follow the loss the curve prescribes.
#include "problems/damping_design/damping_study.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace tailor::damping_study_test {
namespace {

DampingStudyOptions coarse_study() {
  DampingStudyOptions o;
  o.plate.cells_length = 8;
  o.plate.cells_width = 2;
  o.plate.cells_thickness = 1;
  o.plate.controls = {Vector::Constant(1, 0.1), Vector::Constant(1, 3.0)};
  o.vibration.time_step = 4e-3;  // h omega <= 0.27 for the examples
  o.vibration.steps = 300;
  return o;
}

TEST(DampingStudy, DesignedDecayRatesMatchTargets) {
  DampingStudyOptions o = coarse_study();
  const DampingStudy s = run_damping_study(o);
  ASSERT_EQ(s.modes.size(), 3u);
  for (const ModeDecay& d : s.modes) {
    std::printf("mode %d omega %.2f gamma %.2f target %.4e designed %.4e plain %.4e numerical %.2e\n", d.mode,
                d.omega, d.gamma, d.target_rate, d.designed_rate, d.plain_rate, d.numerical_rate);
    if (d.mode < 2) {
      EXPECT_NEAR(d.designed_rate / d.target_rate, 1.0, 0.05) << "mode " << d.mode;
    } else {
      EXPECT_NEAR(d.designed_rate / d.plain_rate, 1.0, 0.05);
    }
    // Plain Rayleigh against the closed form, through the trapezoidal rule's known factor.
    EXPECT_NEAR(d.plain_rate / (d.scheme_factor * d.rayleigh_rate), 1.0, 0.01) << "mode " << d.mode;
    EXPECT_LT(std::abs(d.numerical_rate), 0.05 * d.target_rate) << "mode " << d.mode;
  }
  EXPECT_NEAR(s.modes[0].designed_rate / s.modes[0].plain_rate, 0.1, 0.005);
  EXPECT_NEAR(s.modes[1].designed_rate / s.modes[1].plain_rate, 3.0, 0.15);
  std::printf("implicit Euler: %.4e vs h omega^2/2 = %.4e\n", s.implicit_euler_numerical_rate,
              s.implicit_euler_predicted_rate);
  EXPECT_NEAR(s.implicit_euler_numerical_rate / s.implicit_euler_predicted_rate, 1.0, 0.1);
}

TEST(DampingStudy, NonlinearLossPerCycleFollowsTheCurve) {
  DampingStudyOptions o = coarse_study();
  o.plate.measured_modes = 1;
  o.plate.controls.clear();
  o.vibration.steps = 1;  // the linear part is not measured here
  o.measure_implicit_euler = false;
  o.curve.knots = Vector(4);
  o.curve.knots << 0.0, 0.01, 0.02, 0.04;
  o.curve_controls = Vector(4);
  o.curve_controls << 0.3, 1.0, 3.0, 5.0;
  o.nonlinear_tip_amplitude = 0.05;
  o.nonlinear_steps = 600;
  const DampingStudy s = run_damping_study(o);
  ASSERT_GE(s.cycles.size(), 5u);
  double worst = 0.0;
  for (const NonlinearCycle& c : s.cycles) {
    std::printf("chi %.5f loss %.4e designed %.4e gamma %.3f curve %.3f\n", c.amplitude, c.achieved_loss,
                c.designed_loss, c.achieved_gamma, c.designed_gamma);
    worst = std::max(worst, std::abs(c.achieved_loss / c.designed_loss - 1.0));
  }
  EXPECT_LT(worst, 0.05);
  EXPECT_GT(s.cycles.front().achieved_loss,
            3.0 * s.cycles.back().achieved_loss);  // damping rises with amplitude
}

}  // namespace
}  // namespace tailor::damping_study_test
