// A dynamic pile of rigid boxes with IPC contact (forward/rigid, forward/contact): layers of
// unit boxes (500 kg/m^3, slightly rotated) dropped on a fixed ground and on each other,
// implicit Euler steps of --time-step. Per step: Newton iterations, time, and the shares of the
// contact term's evaluations and of its CCD (max_step, including its broad phase); the number
// of active contact pairs; the smallest distance reached; edge-face crossings (must be 0).
// Writes JSON (--out, default bench_rigid_pile.json) and prints a table.
//
// usage: rigid_pile_bench [--columns 5] [--layers 2] [--steps 100] [--time-step 0.01]
//                         [--max-iterations 100] [--hessian adaptive|projected|exact]
//                         [--force-tolerance F (Newton stops at |g| <= F x total weight)] [--out FILE]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "forward/contact/intersection.hpp"
#include "forward/rigid/rigid_contact_term.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/rigid/rigid_time_stepper.hpp"

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
  }
  void hessian_pattern(HessianPattern& pattern) const override { inner_.hessian_pattern(pattern); }
  double max_step(const Vector& x, const Vector& dx) const override {
    const auto t0 = Clock::now();
    const double step = inner_.max_step(x, dx);
    max_step_seconds += seconds_since(t0);
    return step;
  }
  mutable double evaluate_seconds = 0, max_step_seconds = 0;

 private:
  const EnergyTerm& inner_;
};

}  // namespace

int main(int argc, char** argv) {
  int columns = 5, layers = 2, steps = 100, max_iterations = 100;
  NewtonHessian hessian = NewtonHessian::adaptive;
  double force_tolerance = 0.0;  // Newton's absolute tolerance as a fraction of the total weight
  double dt = 0.01;
  std::string out = "bench_rigid_pile.json";
  std::string hessian_name = "adaptive";
  bench::Cli cli("rigid_pile_bench", "A dynamic pile of rigid boxes with IPC contact, dropped on a ground.");
  cli.integer("--columns", columns, "boxes per row and column of a layer", 1);
  cli.integer("--layers", layers, "layers of boxes", 1);
  cli.steps(steps);
  cli.time_step(dt);
  cli.integer("--max-iterations", max_iterations, "Newton iteration cap per step", 1);
  cli.app()
      .add_option("--hessian", hessian_name, "Newton's Hessian")
      ->type_name("adaptive|projected|exact")
      ->check(cli::one_of({"adaptive", "projected", "exact"}))
      ->capture_default_str();
  cli.number("--force-tolerance", force_tolerance,
             "Newton stops at |g| <= F x total weight (0: the default test)", 0.0, /*inclusive=*/true);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  hessian = hessian_name == "projected" ? NewtonHessian::projected
            : hessian_name == "exact"   ? NewtonHessian::exact
                                        : NewtonHessian::adaptive;
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
  options.stiffness = 1e7;
  const RigidContactTerm contact(system, options);
  const TimedTerm& timed = model.add(std::make_unique<TimedTerm>(contact));
  model.set_elimination(Elimination::dirichlet(system.fixed_dofs(), system.initial_state()));
  NewtonOptions newton;
  newton.max_iterations = max_iterations;
  newton.hessian = hessian;
  newton.absolute_tolerance = force_tolerance * 500.0 * 9.81 * (system.num_bodies() - 1);
  RigidTimeStepper stepper(system, model, inertia, newton);

  bench::Json json = bench::report("rigid_pile");
  json["bodies"] = system.num_bodies() - 1;
  json["time_step"] = dt;
  bench::Json step_rows = bench::Json::array();
  std::printf("%5s %6s %9s %9s %9s %6s %11s %6s\n", "step", "newton", "step s", "contact%", "ccd%", "pairs",
              "min dist", "cross");
  double total = 0, smallest = INFINITY;
  int iterations = 0, crossings_total = 0;
  for (int n = 1; n <= steps; ++n) {
    const double evaluate_before = timed.evaluate_seconds, ccd_before = timed.max_step_seconds;
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
    const double contact_share = (timed.evaluate_seconds - evaluate_before) / seconds;
    const double ccd_share = (timed.max_step_seconds - ccd_before) / seconds;
    const contact::Positions x = system.world_positions(stepper.state());
    const int pairs = contact.potential().num_active(x);
    const double distance = contact.min_distance(stepper.state(), 10.0);
    const int crossings = contact::count_edge_face_intersections(system.surface(), x);
    total += seconds;
    iterations += result.iterations;
    smallest = std::min(smallest, distance);
    crossings_total += crossings;
    std::printf("%5d %6d %9.4f %8.1f%% %8.1f%% %6d %11.3e %6d\n", n, result.iterations, seconds,
                100 * contact_share, 100 * ccd_share, pairs, distance, crossings);
    step_rows.push_back({{"step", n},
                         {"newton_iterations", result.iterations},
                         {"seconds", seconds},
                         {"contact_share", contact_share},
                         {"ccd_share", ccd_share},
                         {"active_pairs", pairs},
                         {"min_distance", distance},
                         {"intersections", crossings}});
  }
  json["steps"] = step_rows;
  json["total_seconds"] = total;
  json["newton_iterations"] = iterations;
  json["min_distance"] = smallest;
  json["intersections"] = crossings_total;
  std::printf("total %.3f s, %d Newton iterations, smallest distance %.3e m, %d intersections\n", total,
              iterations, smallest, crossings_total);
  if (!bench::write_report(out, json, "rigid_pile_bench")) return 1;
  return crossings_total == 0 ? 0 : 1;
}
