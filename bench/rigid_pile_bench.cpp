// A dynamic pile of rigid boxes with IPC contact (forward/rigid, forward/contact): layers of
// unit boxes (500 kg/m^3, slightly rotated) dropped on a fixed ground and on each other,
// implicit Euler steps of --time-step (default 5 x 5 x 2 = 50 boxes). Per step: Newton iterations,
// time, and the shares of the contact term's evaluations, of its CCD (max_step, including its
// broad phase) and of the broad phase alone; the number of active contact pairs; the smallest
// distance reached; edge-face crossings (must be 0); the barrier stiffness; with friction, the
// sliding and sticking pairs. Writes JSON (--out, default bench_rigid_pile.json) and prints a
// table and a summary (medians of the steps, the slowest landing steps).
//
// usage: rigid_pile_bench [--columns 5] [--layers 2] [--steps 100] [--time-step 0.01]
//                         [--max-iterations 100] [--hessian adaptive|projected|exact]
//                         [--force-tolerance F (Newton stops at |g| <= F x total weight)]
//                         [--stiffness fixed|adaptive] [--kappa K (fixed, or adaptive's minimum)]
//                         [--velocity-tolerance V (IPC's stop: Newton direction <= V h; 0 off)]
//                         [--guess previous|predicted] [--friction MU] [--out FILE]
// The defaults are the tuned settings (adaptive kappa from --kappa up to 100 x --kappa, IPC's
// stop at 1e-3 m/s); `--stiffness fixed --velocity-tolerance 0` is the plain Newton of the first
// version.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "forward/contact/broad_phase.hpp"
#include "forward/contact/intersection.hpp"
#include "forward/core/statistics.hpp"
#include "forward/rigid/friction_term.hpp"
#include "forward/rigid/rigid_contact_term.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/rigid/rigid_time_stepper.hpp"

namespace tailor::bench::rigid_pile_bench {

using namespace tailor;
using namespace tailor::rigid;

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Forwards to a contact term and accumulates the time spent in it.
class TimedTerm final : public EnergyTerm {
 public:
  explicit TimedTerm(const EnergyTerm& inner) : inner_(inner) {}
  std::string name() const override { return inner_.name(); }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override {
    const auto t0 = Clock::now();
    inner_.evaluate(x, p, request);
    evaluate_seconds += seconds_since(t0);
    ++calls;
  }
  void hessian_pattern(HessianPattern& pattern) const override { inner_.hessian_pattern(pattern); }
  double max_step(const Vector& x, const Vector& dx) const override {
    const auto t0 = Clock::now();
    const double step = inner_.max_step(x, dx);
    max_step_seconds += seconds_since(t0);
    ++calls;
    return step;
  }
  mutable double evaluate_seconds = 0, max_step_seconds = 0;
  mutable long calls = 0;  // evaluations and CCD queries: one broad phase each

 private:
  const EnergyTerm& inner_;
};

}  // namespace

int run(int argc, char** argv) {
  int columns = 5, layers = 2, steps = 100, max_iterations = 100;
  NewtonHessian hessian = NewtonHessian::adaptive;
  double force_tolerance = 0.0;  // Newton's absolute tolerance as a fraction of the total weight
  double dt = 0.01, kappa = 1e7, velocity_tolerance = 1e-3, friction = 0.0;
  bool adaptive = true;
  InitialGuess guess = InitialGuess::previous;
  std::string out = "bench_rigid_pile.json";
  std::string hessian_name = "adaptive", stiffness_name = "adaptive", guess_name = "previous";
  bench::Cli cli("rigid_pile_bench", "A dynamic pile of rigid boxes with IPC contact, dropped on a ground.");
  cli.integer("--columns", columns, "boxes per row and column of a layer", 1);
  cli.integer("--layers", layers, "layers of boxes", 1);
  cli.steps(steps);
  cli.time_step(dt);
  cli.integer("--max-iterations", max_iterations, "Newton iteration cap per step", 1);
  cli.choice("--hessian", hessian_name, "Newton's Hessian", {"adaptive", "projected", "exact"});
  cli.number("--force-tolerance", force_tolerance,
             "Newton stops at |g| <= F x total weight (0: the default test)", 0.0, /*inclusive=*/true);
  cli.choice("--stiffness", stiffness_name, "barrier stiffness kappa: fixed at --kappa, or adaptive",
             {"fixed", "adaptive"});
  cli.number("--kappa", kappa, "kappa (fixed), or adaptive's minimum", 0.0);
  cli.number("--velocity-tolerance", velocity_tolerance, "IPC's stop: Newton direction <= V h (0: off)", 0.0,
             /*inclusive=*/true);
  cli.choice("--guess", guess_name, "each step's initial guess", {"previous", "predicted"});
  cli.number("--friction", friction, "friction coefficient mu (0: frictionless)", 0.0, /*inclusive=*/true);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  hessian = hessian_name == "projected" ? NewtonHessian::projected
            : hessian_name == "exact"   ? NewtonHessian::exact
                                        : NewtonHessian::adaptive;
  adaptive = stiffness_name == "adaptive";
  guess = guess_name == "predicted" ? InitialGuess::predicted : InitialGuess::previous;
  Eigen::MatrixX3d v;
  Eigen::MatrixX3i f;
  box_surface(Eigen::Vector3d(2.0 * columns + 4, 2.0 * columns + 4, 1), v, f);
  std::vector<RigidBody> bodies;
  RigidBody ground = rigid_body_from_mesh("ground", v, f, 500.0, true);
  ground.position = Eigen::Vector3d(0, 0, -0.5);
  bodies.push_back(ground);
  box_surface(Eigen::Vector3d(1, 1, 1), v, f);
  int index = 0;
  for (int k = 0; k < layers; ++k)
    for (int i = 0; i < columns; ++i)
      for (int j = 0; j < columns; ++j, ++index) {
        RigidBody box = rigid_body_from_mesh("box" + std::to_string(index), v, f, 500.0);
        // Upper layers offset by half a box so that they land across the gaps of the lower.
        const double shift = 0.6 * (k % 2);
        box.position = Eigen::Vector3d(1.5 * i - 0.75 * (columns - 1) + shift,
                                       1.5 * j - 0.75 * (columns - 1) + shift, 1.0 + 1.6 * k);
        box.rotation = Eigen::Vector3d(0.05 * std::sin(1.0 + index), 0.05 * std::cos(2.0 + index),
                                       0.3 * std::sin(index));
        bodies.push_back(box);
      }
  const RigidBodySystem system(bodies);
  Model model(system.num_dofs());
  RigidInertiaTerm& inertia = model.add(std::make_unique<RigidInertiaTerm>(system, dt));
  model.add(std::make_unique<RigidGravityTerm>(system, Eigen::Vector3d(0, 0, -9.81)));
  contact::ContactOptions options;
  options.activation_distance = 0.01;
  options.stiffness = kappa;
  RigidContactTerm contact(system, options);
  const TimedTerm& timed = model.add(std::make_unique<TimedTerm>(contact));
  contact::FrictionOptions friction_options;
  friction_options.coefficient = friction;
  FrictionTerm* friction_term =
      friction > 0.0 ? &model.add(std::make_unique<FrictionTerm>(contact, friction_options)) : nullptr;
  model.set_elimination(Elimination::dirichlet(system.fixed_dofs(), system.initial_state()));
  NewtonOptions newton;
  newton.max_iterations = max_iterations;
  newton.hessian = hessian;
  newton.absolute_tolerance = force_tolerance * 500.0 * 9.81 * (system.num_bodies() - 1);
  RigidStepOptions step_options;
  step_options.contact = &contact;
  step_options.friction = friction_term;
  step_options.initial_guess = guess;
  step_options.velocity_tolerance = velocity_tolerance;
  step_options.stiffness.adaptive = adaptive;
  RigidTimeStepper stepper(system, model, inertia, newton, step_options);

  bench::Json json = bench::report("rigid_pile");
  json["bodies"] = system.num_bodies() - 1;
  json["time_step"] = dt;
  json["stiffness"] = adaptive ? "adaptive" : "fixed";
  json["kappa"] = kappa;
  json["velocity_tolerance"] = velocity_tolerance;
  json["initial_guess"] = guess == InitialGuess::predicted ? "predicted" : "previous";
  json["friction"] = friction;
  bench::Json step_rows = bench::Json::array();
  std::printf("%5s %6s %9s %9s %7s %7s %6s %11s %6s %9s %9s\n", "step", "newton", "step s", "contact%",
              "ccd%", "broad%", "pairs", "min dist", "cross", "kappa", "slide/stick");
  double total = 0, smallest = INFINITY, ccd_total = 0, broad_total = 0;
  int iterations = 0, crossings_total = 0, completed = 0, max_pairs = 0;
  std::vector<int> newton_per_step;
  std::vector<double> seconds_per_step;
  for (int n = 1; n <= steps; ++n) {
    const double evaluate_before = timed.evaluate_seconds, ccd_before = timed.max_step_seconds;
    const long calls_before = timed.calls;
    const auto t0 = Clock::now();
    const NewtonResult result = stepper.step();
    const double seconds = seconds_since(t0);
    if (!result.converged()) {
      std::printf("step %d failed: %s\n%s\n", n, result.message.c_str(), result.report().c_str());
      for (const auto& it : result.history)
        std::printf("  it %3d |g| %.3e alpha %.3e ls %d projected %d\n", it.iteration, it.residual,
                    it.step_length, it.line_search_steps, it.used_projected ? 1 : 0);
      break;
    }
    const RigidStepReport& report = stepper.last_report();
    const double contact_share = (timed.evaluate_seconds - evaluate_before) / seconds;
    const double ccd_seconds = timed.max_step_seconds - ccd_before;
    const contact::Positions x = system.world_positions(stepper.state());
    // The broad phase: one at the step's end timed alone, times the contact term's evaluations and
    // CCD queries of the step (each runs one; the CCD and the initial guess go through the term
    // directly or through the model's max_step).
    double broad_once = INFINITY;  // the fastest of three, against the machine's noise
    for (int repeat = 0; repeat < 3; ++repeat) {
      const auto t_broad = Clock::now();
      (void)contact::find_candidates(system.surface(), x, options.activation_distance);
      broad_once = std::min(broad_once, seconds_since(t_broad));
    }
    const double broad_seconds = broad_once * static_cast<double>(timed.calls - calls_before + 1);
    const int pairs = contact.potential().num_active(x);
    const double distance = contact.min_distance(stepper.state(), 10.0);
    const int crossings = contact::count_edge_face_intersections(system.surface(), x);
    const auto slide_stick =
        friction_term ? friction_term->sliding_and_sticking(stepper.state()) : std::pair<int, int>(0, 0);
    total += seconds;
    ccd_total += ccd_seconds;
    broad_total += broad_seconds;
    iterations += report.newton_iterations;
    newton_per_step.push_back(report.newton_iterations);
    seconds_per_step.push_back(seconds);
    smallest = std::min(smallest, distance);
    max_pairs = std::max(max_pairs, pairs);
    crossings_total += crossings;
    completed = n;
    std::printf("%5d %6d %9.4f %8.1f%% %6.1f%% %6.1f%% %6d %11.3e %6d %9.2e %5d/%d\n", n,
                report.newton_iterations, seconds, 100 * contact_share, 100 * ccd_seconds / seconds,
                100 * broad_seconds / seconds, pairs, distance, crossings, report.stiffness,
                slide_stick.first, slide_stick.second);
    step_rows.push_back({{"step", n},
                         {"newton_iterations", report.newton_iterations},
                         {"seconds", seconds},
                         {"contact_share", contact_share},
                         {"ccd_share", ccd_seconds / seconds},
                         {"broad_phase_share", broad_seconds / seconds},
                         {"active_pairs", pairs},
                         {"min_distance", distance},
                         {"intersections", crossings},
                         {"kappa", report.stiffness},
                         {"initial_step", report.initial_step},
                         {"sliding", slide_stick.first},
                         {"sticking", slide_stick.second}});
  }
  const auto median_of = [](const auto& values) {
    return values.empty() ? 0.0 : median(std::vector<double>(values.begin(), values.end()));
  };
  const int worst =
      newton_per_step.empty() ? 0 : *std::max_element(newton_per_step.begin(), newton_per_step.end());
  const double slowest =
      seconds_per_step.empty() ? 0.0 : *std::max_element(seconds_per_step.begin(), seconds_per_step.end());
  json["steps"] = step_rows;
  json["steps_completed"] = completed;
  json["total_seconds"] = total;
  json["newton_iterations"] = iterations;
  json["median_newton_per_step"] = median_of(newton_per_step);
  json["max_newton_per_step"] = worst;
  json["median_seconds_per_step"] = median_of(seconds_per_step);
  json["max_seconds_per_step"] = slowest;
  json["ccd_share"] = total > 0 ? ccd_total / total : 0.0;
  json["broad_phase_share"] = total > 0 ? broad_total / total : 0.0;
  json["max_active_pairs"] = max_pairs;
  json["min_distance"] = smallest;
  json["intersections"] = crossings_total;
  std::printf(
      "%d of %d steps, total %.3f s, %d Newton iterations (median %.0f, max %d per step), median %.4f s per "
      "step (max %.3f), CCD %.1f%%, broad phase %.1f%% of the time, up to %d active pairs, smallest distance "
      "%.3e m, %d intersections\n",
      completed, steps, total, iterations, median_of(newton_per_step), worst, median_of(seconds_per_step),
      slowest, total > 0 ? 100 * ccd_total / total : 0.0, total > 0 ? 100 * broad_total / total : 0.0,
      max_pairs, smallest, crossings_total);
  if (!bench::write_report(out, json, "rigid_pile_bench")) return 1;
  return crossings_total == 0 && completed == steps ? 0 : 1;
}

}  // namespace tailor::bench::rigid_pile_bench
