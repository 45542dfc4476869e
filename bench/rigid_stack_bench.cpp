// Static stacks of rigid boxes on a fixed ground with IPC contact (forward/rigid,
// forward/contact): columns x columns stacks of `height` unit boxes (1 kg), frictionless, with
// their lateral translation and spin fixed. Reports Newton iterations, time per solve and per
// iteration (assembly, factorization, line search), the cost of one CCD max_step and one broad
// phase, the number of active contact pairs, the smallest distance reached, and the force
// balance (ground reaction vs total weight). Writes JSON (--out, default
// bench_rigid_stack.json) and prints a table.
//
// usage: rigid_stack_bench [--columns 1,3,5] [--height 2] [--out FILE]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "forward/core/model.hpp"
#include "forward/rigid/rigid_contact_term.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::bench::rigid_stack_bench {

using namespace tailor;
using namespace tailor::rigid;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct StackResult {
  int bodies = 0, free_dofs = 0, iterations = 0, active_pairs = 0;
  std::string status;
  double total = 0, assembly = 0, factorization = 0, line_search = 0, max_step = 0, broad_phase = 0;
  double min_distance = 0, ground_force = 0, weight = 0;
};

StackResult run(int columns, int height) {
  const double d_hat = 0.01, g = 9.81;
  Eigen::MatrixX3d v;
  Eigen::MatrixX3i f;
  box_surface(Eigen::Vector3d(2.0 * columns + 2, 2.0 * columns + 2, 1), v, f);
  std::vector<RigidBody> bodies;
  RigidBody ground = rigid_body_from_mesh("ground", v, f, 1.0, true);
  ground.position = Eigen::Vector3d(0, 0, -0.5);
  bodies.push_back(ground);
  box_surface(Eigen::Vector3d(1, 1, 1), v, f);
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j < columns; ++j)
      for (int k = 0; k < height; ++k) {
        RigidBody box = rigid_body_from_mesh("box", v, f, 1.0);
        box.position = Eigen::Vector3d(2.0 * i - (columns - 1), 2.0 * j - (columns - 1),
                                       0.5 + k * (1 + 0.5 * d_hat) + 0.5 * d_hat);
        bodies.push_back(box);
      }
  const RigidBodySystem system(bodies);
  Model model(system.num_dofs());
  model.add(std::make_unique<RigidGravityTerm>(system, Eigen::Vector3d(0, 0, -g)));
  contact::ContactOptions options;
  options.activation_distance = d_hat;
  options.stiffness = 1e5;
  const RigidContactTerm& contact = model.add(std::make_unique<RigidContactTerm>(system, options));
  std::vector<int> fixed = system.fixed_dofs();
  for (int b = 1; b < system.num_bodies(); ++b)
    for (int k : {0, 1, 5}) fixed.push_back(6 * b + k);
  const Vector q0 = system.initial_state();
  model.set_elimination(Elimination::dirichlet(fixed, q0));

  StackResult r;
  r.bodies = system.num_bodies() - 1;
  r.free_dofs = model.elimination().num_free();
  // One CCD query and one broad phase at the start, along a uniform downward motion.
  Vector down = Vector::Zero(q0.size());
  for (int b = 1; b < system.num_bodies(); ++b) down[6 * b + 2] = -d_hat;
  auto t0 = std::chrono::steady_clock::now();
  (void)contact.max_step(q0, down);
  r.max_step = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  (void)contact::find_candidates(system.surface(), system.world_positions(q0), d_hat);
  r.broad_phase = seconds_since(t0);

  NewtonSolver newton(model);
  Vector y = model.elimination().restrict_state(q0);
  t0 = std::chrono::steady_clock::now();
  const NewtonResult result = newton.solve(Vector(), y);
  r.total = seconds_since(t0);
  r.status = to_string(result.status);
  r.iterations = result.iterations;
  for (const auto& it : result.history) {
    r.assembly += it.assembly_seconds;
    r.factorization += it.factorization_seconds;
    r.line_search += it.line_search_seconds;
  }
  const Vector q = model.state(y, Vector());
  r.active_pairs = contact.potential().num_active(system.world_positions(q));
  r.min_distance = contact.min_distance(q, 1.0);
  Vector gradient = Vector::Zero(q.size());
  contact.add_gradient(q, Vector(), gradient);
  r.ground_force = gradient[2];  // -(force on the ground) along z: the weight it carries
  r.weight = r.bodies * g;
  return r;
}

}  // namespace

int run(int argc, char** argv) {
  std::vector<int> columns = {1, 3, 5};
  int height = 2;
  std::string out = "bench_rigid_stack.json";
  bench::Cli cli("rigid_stack_bench", "Static stacks of rigid boxes on a ground with IPC contact.");
  cli.integers("--columns", columns, "stacks per row and column", 1);
  cli.integer("--height", height, "boxes per stack", 1);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  std::printf("%6s %5s %6s %10s %9s %9s %9s %9s %10s %10s %6s %10s %12s %12s\n", "bodies", "dofs", "iters",
              "status", "total s", "assemb s", "factor s", "lsearch s", "ccd s", "broad s", "pairs",
              "min dist", "ground N", "weight N");
  bench::Json json = bench::report("rigid_stack");
  bench::Json runs = bench::Json::array();
  for (const int c : columns) {
    const StackResult r = run(c, height);
    std::printf("%6d %5d %6d %10s %9.4f %9.4f %9.4f %9.4f %10.2e %10.2e %6d %10.3e %12.6f %12.6f\n", r.bodies,
                r.free_dofs, r.iterations, r.status.c_str(), r.total, r.assembly, r.factorization,
                r.line_search, r.max_step, r.broad_phase, r.active_pairs, r.min_distance, r.ground_force,
                r.weight);
    runs.push_back({{"bodies", r.bodies},
                    {"free_dofs", r.free_dofs},
                    {"iterations", r.iterations},
                    {"status", r.status},
                    {"total_seconds", r.total},
                    {"assembly_seconds", r.assembly},
                    {"factorization_seconds", r.factorization},
                    {"line_search_seconds", r.line_search},
                    {"max_step_seconds", r.max_step},
                    {"broad_phase_seconds", r.broad_phase},
                    {"active_pairs", r.active_pairs},
                    {"min_distance", r.min_distance},
                    {"ground_force", r.ground_force},
                    {"weight", r.weight}});
  }
  json["runs"] = runs;
  return bench::write_report(out, json, "rigid_stack_bench") ? 0 : 1;
}

}  // namespace tailor::bench::rigid_stack_bench
