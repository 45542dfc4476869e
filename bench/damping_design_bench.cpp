// Example-based damping on a cantilever plate (Xu & Barbic 2017: "made 10x weaker", "made 3x
// stronger"): measured decay of the two example modes and of a third mode against their
// targets, against plain Rayleigh, and against the trapezoidal rule's numerical damping; and
// a nonlinear curve's per-cycle amplitude loss. Writes OUT/report.json, OUT/envelope.png,
// OUT/gamma_curve.png and OUT/cycle_loss.png (OUT: --out, default damping_design_bench) and
// prints a table.
#include <cstdio>
#include <iostream>
#include <string>

#include "bench_cli.hpp"
#include "problems/damping_design/damping_study.hpp"

namespace tailor::bench::damping_design_bench {

int run(int argc, char** argv) {
  using namespace tailor;
  std::string out = "damping_design_bench";
  bench::Cli cli("damping_design_bench", "Example-based damping on a cantilever plate (Xu & Barbic 2017).");
  cli.out(out, "output folder: report.json and the PNG plots", "DIR");
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  DampingStudyOptions o;
  o.plate.controls = {Vector::Constant(1, 0.1), Vector::Constant(1, 3.0)};
  o.vibration.time_step = 5e-3;
  o.vibration.steps = 1200;
  o.curve.knots = Vector(4);
  o.curve.knots << 0.0, 0.01, 0.02, 0.04;
  o.curve_controls = Vector(4);
  o.curve_controls << 0.3, 1.0, 3.0, 5.0;
  o.nonlinear_tip_amplitude = 0.05;
  o.nonlinear_steps = 2500;
  const DampingStudy s = run_damping_study(o, &std::cout);
  write_damping_study(s, out);
  std::printf("plate: %d DOFs, %d tets, h = %g, %.1f s\n", s.num_dofs, s.num_elements, s.time_step,
              s.seconds);
  std::printf("%5s %9s %6s %11s %11s %11s %11s %9s %9s %10s\n", "mode", "omega", "gamma", "target",
              "designed", "plain", "numerical", "des/tgt", "des/plain", "num/tgt");
  for (const ModeDecay& d : s.modes)
    std::printf("%5d %9.3f %6.2f %11.4e %11.4e %11.4e %11.4e %9.4f %9.4f %10.2e\n", d.mode, d.omega, d.gamma,
                d.target_rate, d.designed_rate, d.plain_rate, d.numerical_rate,
                d.designed_rate / d.target_rate, d.designed_rate / d.plain_rate,
                d.numerical_rate / d.target_rate);
  std::printf("implicit Euler numerical decay of mode 0: %.4e (h omega^2 / 2 = %.4e)\n",
              s.implicit_euler_numerical_rate, s.implicit_euler_predicted_rate);
  std::printf("%10s %12s %12s %10s %10s\n", "amplitude", "loss", "designed", "gamma", "curve");
  for (const NonlinearCycle& c : s.cycles)
    std::printf("%10.5f %12.5e %12.5e %10.4f %10.4f\n", c.amplitude, c.achieved_loss, c.designed_loss,
                c.achieved_gamma, c.designed_gamma);
  return 0;
}

}  // namespace tailor::bench::damping_design_bench
