// Pose-space subspace dynamics on the two-bone arm (forward/rig/, docs/pose_space.md): reduced
// steps per second with the per-pose basis interpolation and cubature on the moving rest shape
// included, against the trajectory error to full-space FEM on the same moving rest shape, for
// r = 10/20/40 on meshes of about 1k/10k (and, with --tets, 50k) tets; precomputation per
// example pose. Writes JSON (default bench_pose_space.json) and prints a table. Timings are
// medians over --repeats runs of --timing-steps steps.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "forward/fem/mass.hpp"
#include "forward/rig/pose_space_dynamics.hpp"
#include "forward/rig/two_bone_arm.hpp"

namespace tailor::bench::pose_space_bench {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct Arm {
  TwoBoneArm arm;
  std::unique_ptr<Rig> rig;
};

// The arm closest to `tets` tets: cells along = 16 k, across = 3 k / 2 (6 tets per cell).
Arm make_arm(int tets) {
  int best_along = 16, best_across = 3;
  double best = 1e300;
  for (int across = 2; across <= 20; ++across) {
    const int along = std::max(4, static_cast<int>(std::lround(across * 16.0 / 3.0)));
    const double diff = std::abs(std::log(6.0 * along * across * across / tets));
    if (diff < best) best = diff, best_along = along, best_across = across;
  }
  TwoBoneArmOptions options;
  options.cells_along = best_along;
  options.cells_across = best_across;
  options.youngs_modulus = 1e6;
  Arm a;
  a.arm = two_bone_arm(options);
  a.rig = std::make_unique<Rig>(a.arm.bones, a.arm.body.mesh.rest_positions, a.arm.weights);
  return a;
}

// The elbow flexes to -1.6 rad in 0.3 s and swings back halfway by 0.6 s; the shoulder lifts.
PoseTrajectory elbow_motion() {
  return PoseTrajectory({0.0, 0.3, 0.6}, {Vector::Zero(2), Eigen::Vector2d(0.2, -1.6), Eigen::Vector2d(0.1, -0.8)});
}

MovingRestOptions dynamics_options(int newton) {
  MovingRestOptions o;
  o.time_step = 0.01;
  o.rayleigh_mass = 1.0;
  o.max_newton_iterations = newton;
  return o;
}

struct Row {
  int tets = 0, rank = 0, cubature_elements = 0;
  double steps_per_s = 0, trajectory_error = 0;
  // The best the blended basis can do: the full-space trajectory's M-orthogonal projection on
  // U(p(t_n)), sqrt(sum_n |u_n - U U^T M u_n|^2 / sum_n |u_n|^2). Near trajectory_error: the basis
  // content limits the error; far below it: the reduced dynamics (neglected dU/dt, cubature) do.
  double projection_error = 0;
  std::vector<ExamplePosePrecomputation> poses;
};

std::vector<Vector> full_space(const Arm& a, int steps, double& seconds_per_step) {
  const MovingRestDynamics full(*a.rig, a.arm.body, dynamics_options(30));
  const PoseTrajectory motion = elbow_motion();
  MovingRestState s = full.initial_state(), next;
  std::vector<Vector> u;
  const auto t = Clock::now();
  for (int k = 0; k < steps; ++k) {
    int iterations = 0;
    std::string message;
    if (!full.step(motion, s, next, iterations, message)) throw std::runtime_error(message);
    s = next;
    u.push_back(s.u);
  }
  seconds_per_step = since(t) / steps;
  return u;
}

Row reduced(const Arm& a, int r, const std::vector<Vector>& reference, int timing_steps, int repeats, int newton,
            int cubature_elements, int example_poses) {
  PoseSpaceOptions options;
  options.basis.linear_modes = std::min(r, std::max(6, r / 2));
  options.basis.derivative_modes = 4;
  options.basis.size = r;
  options.cubature.max_elements = cubature_elements;
  options.cubature.tolerance = 1e-3;
  std::vector<ExamplePose> examples;
  // Elbow angles evenly spaced over the motion's range [-1.6, 0] (3: 0, -0.8, -1.6).
  for (int i = 0; i < example_poses; ++i)
    examples.push_back({Eigen::Vector2d(0.1, example_poses == 1 ? -0.8 : -1.6 * i / (example_poses - 1.0)), Matrix()});
  const PoseSpaceDynamics dynamics(*a.rig, a.arm.body, examples, options, dynamics_options(newton));
  Row row;
  row.tets = a.arm.body.mesh.num_elements();
  row.rank = r;
  row.poses = dynamics.precomputation();
  row.cubature_elements = dynamics.cubature_elements();
  const PoseTrajectory motion = elbow_motion();
  auto run = [&](int steps, const std::function<void(int, const ReducedRigState&)>& visit) {
    ReducedRigState s = dynamics.initial_state(), next;
    for (int k = 0; k < steps; ++k) {
      int iterations = 0;
      std::string message;
      if (!dynamics.step(motion, s, next, iterations, message)) throw std::runtime_error(message);
      s = next;
      if (visit) visit(k, s);
    }
  };
  double error2 = 0, norm2 = 0;
  run(static_cast<int>(reference.size()), [&](int k, const ReducedRigState& s) {
    const Vector u = dynamics.displacement(motion(s.time).p, s.q);
    error2 += (u - reference[static_cast<std::size_t>(k)]).squaredNorm();
    norm2 += reference[static_cast<std::size_t>(k)].squaredNorm();
  });
  row.trajectory_error = std::sqrt(error2 / norm2);
  const SparseMatrix mass = mass_matrix(a.arm.body.mesh, a.arm.body.density, MassLumping::consistent);
  double projection2 = 0;
  for (std::size_t k = 0; k < reference.size(); ++k) {
    const Matrix u = dynamics.basis().blend(dynamics.weights(motion(0.01 * static_cast<double>(k + 1)).p));
    const Vector& f = reference[k];
    projection2 += (f - u * (u.transpose() * (mass * f))).squaredNorm();
  }
  row.projection_error = std::sqrt(projection2 / norm2);
  std::vector<double> rates;
  for (int k = 0; k < repeats; ++k) {
    const auto t = Clock::now();
    run(timing_steps, nullptr);
    rates.push_back(timing_steps / since(t));
  }
  std::sort(rates.begin(), rates.end());
  row.steps_per_s = rates[rates.size() / 2];
  return row;
}

Json to_json(const Row& row) {
  Json j;
  j["tets"] = row.tets;
  j["r"] = row.rank;
  j["steps_per_second_median"] = row.steps_per_s;
  j["trajectory_error"] = row.trajectory_error;
  j["projection_error"] = row.projection_error;
  j["cubature_elements_union"] = row.cubature_elements;
  Json poses = Json::array();
  for (const ExamplePosePrecomputation& p : row.poses)
    poses.push_back({{"basis_seconds", p.basis_seconds},
                     {"cubature_seconds", p.cubature_seconds},
                     {"cubature_elements", p.cubature_elements},
                     {"training_error", p.training_error}});
  j["example_poses"] = poses;
  return j;
}

}  // namespace

int run(int argc, char** argv) {
  std::vector<int> tets = {1000, 10000}, ranks = {10, 20, 40};
  int steps = 60, timing_steps = 1000, repeats = 3, newton = 1, cubature_elements = 60, example_poses = 3;
  std::string out = "bench_pose_space.json";
  Cli cli("pose_space_bench", "Pose-space subspace dynamics of the two-bone arm: reduced steps/s against error.");
  cli.tets(tets);
  cli.integers("--ranks", ranks, "basis sizes r", 1);
  cli.steps(steps, "steps compared with the full space (h = 0.01 s)");
  cli.integer("--timing-steps", timing_steps, "reduced steps per timed run", 1);
  cli.repeats(repeats);
  cli.integer("--newton", newton, "Newton iterations per reduced step (1: linearly implicit)", 1);
  cli.integer("--cubature-elements", cubature_elements, "cubature elements per example pose at most", 1);
  cli.integer("--example-poses", example_poses, "example poses, elbow angles evenly spaced over [-1.6, 0]", 1);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;

  Json report_json = report("pose_space");
  report_json["settings"] = {{"steps", steps},          {"time_step", 0.01},
                             {"timing_steps", timing_steps}, {"repeats", repeats},
                             {"newton_iterations", newton},  {"cubature_elements_per_pose", cubature_elements},
                             {"example_poses", example_poses}};
  Json meshes = Json::array();
  std::printf("%8s %4s %12s %10s %10s %9s %14s %14s %10s\n", "tets", "r", "steps/s", "error", "proj err",
              "cubature", "basis s/pose", "cubature s/pose", "train err");
  for (int target : tets) {
    const Arm a = make_arm(target);
    double full_seconds = 0;
    const std::vector<Vector> reference = full_space(a, steps, full_seconds);
    Json mesh = {{"tets", a.arm.body.mesh.num_elements()},
                 {"vertices", a.arm.body.mesh.num_vertices()},
                 {"full_space_seconds_per_step", full_seconds}};
    Json rows = Json::array();
    std::printf("%8d %4s %12.1f %10s   (full space, Newton + CHOLMOD)\n", a.arm.body.mesh.num_elements(), "-",
                1.0 / full_seconds, "0");
    for (int r : ranks) {
      const Row row = reduced(a, r, reference, timing_steps, repeats, newton, cubature_elements, example_poses);
      double basis_s = 0, cubature_s = 0, train = 0;
      for (const auto& p : row.poses) basis_s += p.basis_seconds, cubature_s += p.cubature_seconds, train = std::max(train, p.training_error);
      const double m = static_cast<double>(row.poses.size());
      std::printf("%8d %4d %12.1f %10.3e %10.3e %9d %14.2f %14.2f %10.1e\n", row.tets, r, row.steps_per_s,
                  row.trajectory_error, row.projection_error, row.cubature_elements, basis_s / m, cubature_s / m,
                  train);
      std::fflush(stdout);
      rows.push_back(to_json(row));
    }
    mesh["reduced"] = rows;
    meshes.push_back(mesh);
  }
  report_json["meshes"] = meshes;
  return write_report(out, report_json, "pose_space_bench") ? 0 : 1;
}

}  // namespace tailor::bench::pose_space_bench
