// Speed against error of local reduced models at equal reduced size r: a global basis (linear
// modes + modal derivatives), domain decomposition (Craig-Bampton: fixed-interface modes, local
// modal derivatives of fixed-interface and boundary-driven modes, the gravity load's interior responses, boundary-driven modes from the
// interface traces of global modes) and
// overlapping domains (global modes + derivatives blended by principal-direction weights),
// each against full-space dynamics of the same model, scheme and time step.
//
// Scene: a 4 x 1 x 1 StVK cantilever (E = 5e6 unless --youngs, nu = 0.3, density 1000,
// consistent mass), clamped at x = 0, at rest when gravity (9.81, downwards) is switched on at
// t = 0 (the tip falls by ~30% of the length with the default E). Newmark average acceleration,
// h = 1/100 s, Rayleigh beta = 1e-3 s, --steps steps. The default mesh is the published
// configuration (Yang et al. 2015, "funnelling the bunny": 64K tets, 5 domains, 150 reduced
// DOFs, h = 1/100): bench::cantilever_cells(64000) = 63,882 tets.
//
// Reduced energies: the domain and overlapping bases use the grouped exact StVK polynomial
// (local_reduced_stvk.hpp; Newton with the Jacobian every iteration); a global basis of r = 150
// has a (r + r(r+1)/2)^2 = 1 GB polynomial, so it uses the projected model (cost proportional
// to the mesh; the Jacobian once per step). Reported per basis: precomputation (wall; every step
// from the mesh to the reduced model), median steps/s (wall), Newton iterations per step,
// trajectory error sqrt(sum_n |u_r - u_f|^2_M / sum_n |u_f|^2_M) and peak tip error, and how
// many steps completed (a failed Newton step stops the run). Also per basis: wall and process
// CPU seconds of every precomputation phase (domain_decomposition's phases, the global modes,
// the overlap weights, the reduced model), the per-step medians of wall and CPU time and of the
// part spent evaluating the reduced force and tangent, and /proc/loadavg before and after (CPU
// seconds are the figure of the work on a shared machine). Writes JSON (--out) and a table.
//
// usage: domain_reduction_bench [--tets 64000] [--steps 100] [--size 150] [--domains 5]
//          [--fixed-interface-modes 11] [--derivative-modes 3] [--boundary-derivative-modes 3]
//          [--interface-modes 30]
//          [--overlap-layers 2] [--youngs 5e6] [--bases global,domains,overlapping] [--no-reference]
//          [--out FILE]
//        domain_reduction_bench --twist T [--twist-cells 24] [--twist-steps 40] [--twist-size 51]
//          [--twist-domains 6] [--twist-load end|distributed] [--twist-bend g] [--twist-time-step 0.02]
//          [--twist-material stvk|neo_hookean] [--twist-interface-modes 6] [--twist-fixed-interface-modes 4]
//          [--twist-blends linear,quaternion,nearest] [--twist-bases global,domains,overlapping]
//          [--twist-newton-iterations 30] [--twist-reference-substeps 1] [--twist-rigid-columns]
//          (the twisted bar with per-domain rotations, below)
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "bench_cli.hpp"
#include "cantilever.hpp"
#include "forward/dynamics/setup.hpp"
#include "forward/dynamics/time_integrator.hpp"
#include "forward/fem/mass.hpp"
#include "forward/reduction/domain_decomposition.hpp"
#include "forward/reduction/domain_partition.hpp"
#include "forward/reduction/domain_rotations.hpp"
#include "forward/reduction/free_stiffness_factor.hpp"
#include "forward/reduction/free_space.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/reduction/local_reduced_stvk.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/reduction/modal_derivatives.hpp"
#include "forward/reduction/overlapping_domains.hpp"
#include "forward/reduction/projected_reduced_model.hpp"
#include "forward/reduction/reduced_dynamics.hpp"
#include "forward/reduction/rotating_subspace_dynamics.hpp"
#include "tailor_version.hpp"

namespace tailor::bench::domain_reduction_bench {

using namespace tailor;
using bench::Clock;
using bench::median;
using bench::seconds_since;

namespace {

constexpr double kLength = 4.0, kPoisson = 0.3, kDensity = 1000.0, kGravity = 9.81, kBeta = 1e-3, kStep = 0.01;

struct Settings {
  int size = 150, domains = 5, fixed_interface_modes = 11, derivative_modes = 3, boundary_derivative_modes = 3;
  int interface_modes = 30;
  int overlap_layers = 2, steps = 100;
  bool reference = true;  // --no-reference: speed only (the full-space run dominates on large meshes)
  double youngs = 5e6;
};

struct Row {
  std::string basis, energy;
  int r = 0, groups = 1, largest_group = 0, completed = 0;
  double precompute_s = 0, precompute_cpu_s = 0, steps_per_s = 0, newton_per_step = 0, trajectory_error = 0;
  double peak_tip_error = 0;
  // Per step, medians: wall and CPU of the whole step and of the reduced model's evaluations
  // (force and tangent) in it; the rest of a step is the dense Newton solve and bookkeeping.
  double step_wall_s = 0, step_cpu_s = 0, evaluate_wall_s = 0, evaluate_cpu_s = 0, evaluations_per_step = 0;
  double load_before = 0, load_after = 0;  // /proc/loadavg's 1-minute load around the row
  double coefficient_mb = 0;               // the local polynomial's packed coefficients
  std::vector<PhaseTiming> phases;         // precomputation, in order
  std::string message;
};

// The machine's 1-minute load average (0 when unknown): the bench shares the cores.
double load_average() {
  std::ifstream in("/proc/loadavg");
  double load = 0.0;
  in >> load;
  return load;
}

// Times every evaluation of a reduced model (wall and process CPU, accumulated until reset).
class TimedModel final : public ReducedElasticModel {
 public:
  explicit TimedModel(const ReducedElasticModel& inner) : inner_(inner) {}
  int size() const override { return inner_.size(); }
  void evaluate(const Vector& q, double* energy, Vector* force, Matrix* stiffness) const override {
    const auto t0 = Clock::now();
    const double c0 = bench::cpu_seconds();
    inner_.evaluate(q, energy, force, stiffness);
    wall_ += seconds_since(t0);
    cpu_ += bench::cpu_seconds() - c0;
    ++count_;
  }
  void reset() const { wall_ = cpu_ = 0.0, count_ = 0; }
  double wall() const { return wall_; }
  double cpu() const { return cpu_; }
  int count() const { return count_; }

 private:
  const ReducedElasticModel& inner_;
  mutable double wall_ = 0.0, cpu_ = 0.0;
  mutable int count_ = 0;
};

struct Scene {
  bench::Cantilever elastic;
  Vector p;
  SparseMatrix mass;
  Vector gravity_force;  // M g
};

Eigen::Vector3d tip_point(const Vector& u, const std::vector<int>& tip) {
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (int v : tip) t += u.segment<3>(3 * v);
  return t / static_cast<double>(tip.size());
}

// Full-space Newmark displacements per state (num_dofs x (steps + 1)) and the median step time.
Matrix full_space_reference(const bench::CantileverCells& cells, const Settings& s, double& step_s) {
  DynamicTerms terms;
  bench::Cantilever full =
      bench::make_cantilever(kLength, cells, MaterialKind::stvk, [&](Model& model, const Mesh& mesh) {
        terms = add_dynamics_terms(
            model, mesh, DynamicsSetup{MassLumping::consistent, Eigen::Vector3d(0, 0, -kGravity), true});
      });
  const int m = full.mesh.num_elements();
  Vector p = bench::cantilever_parameters(full, s.youngs, kPoisson);
  p.segment(terms.density_offset, m).setConstant(kDensity);
  p[terms.alpha_offset] = 0.0;
  p[terms.beta_offset] = kBeta;
  TimeIntegratorOptions options;
  options.scheme = TimeScheme::newmark;
  options.time_step = kStep;
  TimeIntegrator integrator(*full.model, options);
  DynamicState state = integrator.initial_state(full.rest, Vector::Zero(full.rest.size()), p);
  Matrix u(full.rest.size(), s.steps + 1);
  u.col(0).setZero();
  std::vector<double> wall;
  for (int n = 0; n < s.steps; ++n) {
    const auto t0 = Clock::now();
    const NewtonResult r = integrator.step(state, p);
    wall.push_back(seconds_since(t0));
    if (!r.converged()) throw std::runtime_error("full-space step " + std::to_string(n + 1) + ": " + r.message);
    u.col(n + 1) = state.x - full.rest;
  }
  step_s = median(wall);
  return u;
}

// Modes + modal derivatives of the lowest m modes with m + m (m + 1) / 2 >= r, M-orthonormal, first r.
Matrix modes_and_derivatives(const Scene& scene, const ModalAnalysis& modes, int r) {
  int m = 1;
  while (m + m * (m + 1) / 2 < r) ++m;
  const Matrix psi = modal_derivatives(*scene.elastic.model, scene.elastic.rest, scene.p, modes.modes.leftCols(m));
  Matrix all(modes.modes.rows(), m + psi.cols());
  all << modes.modes.leftCols(m), psi;
  const Matrix basis = mass_orthonormal_basis(all, scene.mass);
  return basis.leftCols(std::min<Eigen::Index>(r, basis.cols()));
}

// Newmark steps of the reduced model from rest under gravity; errors against the reference.
void simulate(const ReducedElasticModel& untimed, const Matrix& basis, ReducedJacobian jacobian, const Scene& scene,
              const Matrix& reference, int steps, Row& row) {
  const TimedModel model(untimed);
  ReducedDynamicsOptions options;
  options.integrator = ReducedIntegrator::newmark;
  options.time_step = kStep;
  options.rayleigh_stiffness = kBeta;
  options.newton_tolerance = 1e-10;
  options.jacobian = jacobian;
  const ReducedDynamics dynamics(model, options, Matrix(), basis.transpose() * scene.gravity_force);
  ReducedState state = dynamics.initial_state(Vector::Zero(basis.cols()), Vector::Zero(basis.cols()));
  std::vector<double> wall, cpu, evaluate_wall, evaluate_cpu, evaluations;
  double error2 = 0.0, norm2 = 0.0;
  int newton_total = 0;
  const std::vector<int>& tip = scene.elastic.tip_vertices;
  for (int n = 0; n < steps; ++n) {
    ReducedState next;
    int newton = 0;
    model.reset();
    const auto t0 = Clock::now();
    const double c0 = bench::cpu_seconds();
    const bool ok = dynamics.step(state, next, newton, row.message);
    wall.push_back(seconds_since(t0));
    cpu.push_back(bench::cpu_seconds() - c0);
    evaluate_wall.push_back(model.wall());
    evaluate_cpu.push_back(model.cpu());
    evaluations.push_back(model.count());
    if (!ok || !next.q.allFinite()) break;
    newton_total += newton;
    state = std::move(next);
    row.completed = n + 1;
    if (reference.cols() == 0) continue;
    const Vector u = basis * state.q, e = u - reference.col(n + 1);
    error2 += e.dot(scene.mass * e);
    norm2 += reference.col(n + 1).dot(scene.mass * reference.col(n + 1));
    row.peak_tip_error =
        std::max(row.peak_tip_error, (tip_point(u, tip) - tip_point(reference.col(n + 1), tip)).norm());
  }
  row.steps_per_s = 1.0 / median(wall);
  row.step_wall_s = median(wall);
  row.step_cpu_s = median(cpu);
  row.evaluate_wall_s = median(evaluate_wall);
  row.evaluate_cpu_s = median(evaluate_cpu);
  row.evaluations_per_step = median(evaluations);
  row.newton_per_step = row.completed > 0 ? static_cast<double>(newton_total) / row.completed : 0.0;
  row.trajectory_error = norm2 > 0.0 ? std::sqrt(error2 / norm2) : std::nan("");  // null in JSON
}

Row run_basis(const std::string& kind, const Scene& scene, const Settings& s, const Eigen::VectorXi& domains,
              const Matrix& reference) {
  Row row;
  row.basis = kind;
  row.load_before = load_average();
  const auto t = Clock::now();
  const double c = bench::cpu_seconds();
  PhaseClock clock;
  const auto& mesh = scene.elastic.mesh;
  const auto& model = *scene.elastic.model;
  Matrix basis;
  if (kind == "domains") {
    DomainDecompositionOptions options;
    options.fixed_interface_modes = s.fixed_interface_modes;
    options.derivative_modes = s.derivative_modes;
    options.boundary_derivative_modes = s.boundary_derivative_modes;
    options.interface_modes = s.interface_modes;
    options.loads = scene.gravity_force;  // the static correction of the body load (Craig-Bampton)
    DomainDecomposition dd = domain_decomposition(model, mesh, scene.elastic.rest, scene.p, scene.mass, domains, options);
    basis = std::move(dd.basis);
    row.phases = std::move(dd.phases);
    clock.restart();
  } else {
    ModalAnalysisOptions modal;
    const int local = kind == "global" ? s.size : s.size / s.domains;
    int m = 1;
    while (m + m * (m + 1) / 2 < local) ++m;
    modal.count = m;
    const ModalAnalysis modes = modal_analysis(model, 3, scene.elastic.rest, scene.p, scene.mass, modal);
    clock.add(row.phases, "global modes");
    basis = modes_and_derivatives(scene, modes, local);
    clock.add(row.phases, "global modal derivatives, M-orthonormalization");
    if (kind == "overlapping") {
      OverlappingDomainOptions options;
      options.overlap_layers = s.overlap_layers;
      const OverlappingDomains od =
          overlapping_domains(model, mesh, scene.elastic.rest, scene.p, scene.mass, domains, options);
      clock.add(row.phases, "overlap weights (principal directions)");
      basis = mass_orthonormal_basis(blended_basis(od.weights, basis, 3), scene.mass, 1e-8);
      clock.add(row.phases, "blended basis, M-orthonormalization");
    }
  }
  row.r = static_cast<int>(basis.cols());
  if (kind == "global") {
    row.energy = "projected";
    const ProjectedReducedModel projected(model, scene.p, scene.elastic.rest, basis);
    clock.add(row.phases, "projected model");
    row.precompute_s = seconds_since(t);
    row.precompute_cpu_s = bench::cpu_seconds() - c;
    simulate(projected, basis, ReducedJacobian::once_per_step, scene, reference, s.steps, row);
  } else {
    row.energy = "local polynomial";
    const LocalReducedStvk local(model, mesh, scene.p, basis, 1e-14 * basis.cwiseAbs().maxCoeff());
    clock.add(row.phases, "reduced polynomial (local, grouped)");
    row.groups = local.groups();
    row.largest_group = local.largest_group();
    row.coefficient_mb = 1e-6 * static_cast<double>(local.coefficient_bytes());
    row.precompute_s = seconds_since(t);
    row.precompute_cpu_s = bench::cpu_seconds() - c;
    simulate(local, basis, ReducedJacobian::every_iteration, scene, reference, s.steps, row);
  }
  row.load_after = load_average();
  std::printf("  %-12s r = %3d (%s, %d groups of <= %d columns): precompute %.1f s (CPU %.1f s), %.1f steps/s, "
              "%.2f Newton/step, trajectory error %.3e, peak tip error %.4f, %d/%d steps, load %.1f -> %.1f\n",
              row.basis.c_str(), row.r, row.energy.c_str(), row.groups, row.largest_group, row.precompute_s,
              row.precompute_cpu_s, row.steps_per_s, row.newton_per_step, row.trajectory_error, row.peak_tip_error,
              row.completed, s.steps, row.load_before, row.load_after);
  std::printf("    %-52s %9s %9s\n", "phase", "wall s", "CPU s");
  for (const PhaseTiming& ph : row.phases) std::printf("    %-52s %9.2f %9.2f\n", ph.name.c_str(), ph.wall_s, ph.cpu_s);
  std::printf("    per step (median): %.2f ms wall, %.2f ms CPU; reduced force + tangent %.2f ms wall, %.2f ms CPU "
              "in %.0f evaluations; the rest (dense solve) %.2f ms wall\n",
              1e3 * row.step_wall_s, 1e3 * row.step_cpu_s, 1e3 * row.evaluate_wall_s, 1e3 * row.evaluate_cpu_s,
              row.evaluations_per_step, 1e3 * (row.step_wall_s - row.evaluate_wall_s));
  std::fflush(stdout);
  return row;
}


// ---- Large rotations: a bar twisted by a dead torque (docs/reduction.md, "Per-domain rotations").
// A 4 x 0.5 x 0.5 StVK bar (E = 1e6, nu = 0.3, density 100, consistent mass), clamped at x = 0,
// no gravity; a dead torque T about the bar's axis, either on its free end (tangential forces on
// the end vertices, f_v = T (e_x x r_v) / sum |r_v|^2, r_v from the axis) or distributed over the
// whole bar like a body load (f_v = T m_v (e_x x r_v) / sum m_v |r_v|^2, m_v the vertex masses:
// no end face is crushed), optionally with a dead transverse body load m_v g (-e_z) that bends
// the bar (--twist-bend g). Newmark, h =
// 0.02 s, Rayleigh beta = 1e-3 s, every basis stepped by RotatingSubspaceDynamics (the same
// incremental potential and Newton), rotations off or on with each chosen blend; "full" is the same scheme with the
// identity on the free DOFs as its basis (full-space Newmark). Reported: steps completed, total
// energy at the last step and its largest value (0 at rest; with damping it must not rise),
// smallest element volume ratio, trajectory error against full space over the steps both completed.
struct TwistSettings {
  double torque = 0.0, time_step = 0.02, bend = 0.0;
  int along = 24, across = 3, steps = 40, size = 51, domains = 6, overlap_layers = 2;
  int fixed_interface_modes = 4, interface_modes = 6;  // the domain basis (interface_modes 0: every interface DOF)
  int newton_iterations = 30;                 // per step, every row
  int reference_substeps = 1;                 // full space takes this many steps of h / k per step
  bool rigid_columns = false;                 // overlapping: each domain's six rigid motions among its columns
  std::vector<std::string> bases = {"global", "domains", "overlapping"};  // besides full space
  std::string load = "end";                   // "end" or "distributed"
  std::string material = "stvk";              // or "neo_hookean"
  std::vector<std::string> blends = {"linear"};  // rotation blends of the rows with rotations
};

RotationBlend parse_blend(const std::string& name) {
  return name == "quaternion" ? RotationBlend::quaternion
                              : name == "nearest" ? RotationBlend::nearest : RotationBlend::linear;
}

struct TwistRow {
  std::string basis, blend = "no";
  bool rotations = false;
  int r = 0, completed = 0;
  double precompute_s = 0, steps_per_s = 0, newton_per_step = 0, final_energy = 0, largest_energy = 0;
  double smallest_volume_ratio = 1, trajectory_error = 0, tip_angle = 0, largest_tip_angle = 0;
  std::string message;
};

// The end face's twist angle: the mean rotation of its vertices about the axis (atan2 of the
// cross and dot products of the rest and current radial vectors in the y-z plane).
double twist_angle(const Mesh& mesh, const std::vector<int>& tip, const Vector& u) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (int v : tip) c += mesh.rest_positions.row(v).tail<2>().transpose();
  c /= static_cast<double>(tip.size());
  double sum = 0.0;
  int count = 0;
  for (int v : tip) {
    const Eigen::Vector2d r = mesh.rest_positions.row(v).tail<2>().transpose() - c;
    if (r.norm() < 1e-9) continue;
    const Eigen::Vector2d q = r + u.segment<2>(3 * v + 1);
    sum += std::atan2(r.x() * q.y() - r.y() * q.x(), r.dot(q));
    ++count;
  }
  return count > 0 ? sum / count : 0.0;
}

TwistRow twist_run(const std::string& kind, const std::string& blend, const bench::Cantilever& bar, const Vector& p,
                   const SparseMatrix& mass, const Vector& torque, const TwistSettings& t, const Matrix& reference,
                   Matrix* trajectory) {
  TwistRow row;
  const bool rotations = blend != "no";
  row.basis = kind;
  row.blend = blend;
  row.rotations = rotations;
  const auto t0 = Clock::now();
  const Model& model = *bar.model;
  const Mesh& mesh = bar.mesh;
  const Eigen::VectorXi partition = partition_elements(mesh, kind == "global" || kind == "full" ? 1 : t.domains);
  Matrix basis, weights = domain_vertex_weights(mesh, partition);
  if (kind == "full") {
    std::vector<bool> fixed(static_cast<std::size_t>(bar.rest.size()), false);
    for (int dof : bar.fixed_dofs) fixed[static_cast<std::size_t>(dof)] = true;
    basis = Matrix::Zero(bar.rest.size(), bar.rest.size() - static_cast<Eigen::Index>(bar.fixed_dofs.size()));
    for (Eigen::Index i = 0, c = 0; i < bar.rest.size(); ++i)
      if (!fixed[static_cast<std::size_t>(i)]) basis(i, c++) = 1.0;
  } else if (kind == "domains") {
    DomainDecompositionOptions options;
    options.fixed_interface_modes = t.fixed_interface_modes;
    options.derivative_modes = 1;
    options.boundary_derivative_modes = 1;
    options.interface_modes = t.interface_modes;
    options.loads = Matrix(torque);
    basis = domain_decomposition(model, mesh, bar.rest, p, mass, partition, options).basis;
  } else {
    // Global candidates: the torque's static response, the lowest modes and the modal derivatives
    // of the lowest m modes and the response; the first `local` M-orthonormal columns.
    const int local = kind == "global" ? t.size : std::max(1, t.size / t.domains);
    int m = 1;
    while (m + 1 + (m + 1) * (m + 2) / 2 < local) ++m;
    ModalAnalysisOptions modal;
    modal.count = std::max(m, local);
    const ModalAnalysis modes = modal_analysis(model, 3, bar.rest, p, mass, modal);
    const Vector response = FreeStiffnessFactor(model, bar.rest, p).solve(torque);
    Matrix seeds(bar.rest.size(), m + 1);
    seeds << response / std::sqrt(response.dot(mass * response)), modes.modes.leftCols(m);
    const Matrix psi = modal_derivatives(model, bar.rest, p, seeds);
    Matrix all(bar.rest.size(), 1 + m + psi.cols() + modes.modes.cols() - m);
    all << seeds, psi, modes.modes.rightCols(modes.modes.cols() - m);
    basis = mass_orthonormal_basis(all, mass);
    basis = basis.leftCols(std::min<Eigen::Index>(local, basis.cols())).eval();
    if (kind == "overlapping" && t.rigid_columns) {
      // The bar's six rigid motions (zero on the supports), blended below by each domain's
      // weights: every domain can translate and turn (to first order) without straining.
      Matrix rigid = rigid_body_motions(bar.rest, 3);
      for (int dof : bar.fixed_dofs) rigid.row(dof).setZero();
      Matrix both(bar.rest.size(), 6 + basis.cols());
      both << rigid, basis;
      basis = mass_orthonormal_basis(both, mass);
      basis = basis.leftCols(std::min<Eigen::Index>(local, basis.cols())).eval();
    }
    if (kind == "overlapping") {
      OverlappingDomainOptions options;
      options.overlap_layers = t.overlap_layers;
      weights = overlapping_domains(model, mesh, bar.rest, p, mass, partition, options).weights;
      basis = mass_orthonormal_basis(blended_basis(weights, basis, 3), mass, 1e-8);
    }
  }
  row.r = static_cast<int>(basis.cols());
  RotatingSubspaceOptions options;
  const int substeps = kind == "full" ? t.reference_substeps : 1;
  options.time_step = t.time_step / substeps;
  options.rayleigh_stiffness = kBeta;
  options.rotations = rotations;
  options.max_newton_iterations = t.newton_iterations;
  if (rotations) options.blend = parse_blend(blend);
  const RotatingSubspaceDynamics dynamics(model, mesh, p, bar.rest, mass, torque, basis, weights, options);
  row.precompute_s = seconds_since(t0);
  SubspaceState state = dynamics.initial_state(Vector::Zero(bar.rest.size()));
  if (trajectory) *trajectory = Matrix::Zero(bar.rest.size(), t.steps + 1);
  std::vector<double> wall;
  int newton_total = 0;
  double error2 = 0.0, norm2 = 0.0;
  row.largest_energy = 0.0;
  for (int n = 0; n < t.steps; ++n) {
    bool ok = true;
    const auto ts = Clock::now();
    for (int k = 0; k < substeps && ok; ++k) {
      SubspaceState next;
      int newton = 0;
      ok = dynamics.step(state, next, newton, row.message);
      if (ok) state = std::move(next);
      newton_total += newton;
    }
    wall.push_back(seconds_since(ts));
    if (!ok) {
      row.message = "step " + std::to_string(n + 1) + ": " + row.message;
      break;
    }
    row.completed = n + 1;
    row.final_energy = dynamics.total_energy(state);
    row.largest_energy = std::max(row.largest_energy, row.final_energy);
    row.smallest_volume_ratio = std::min(row.smallest_volume_ratio, dynamics.smallest_volume_ratio(state.u));
    row.tip_angle = twist_angle(mesh, bar.tip_vertices, state.u);
    row.largest_tip_angle = std::max(row.largest_tip_angle, std::abs(row.tip_angle));
    if (trajectory) trajectory->col(n + 1) = state.u;
    if (reference.cols() > n + 1) {
      const Vector e = state.u - reference.col(n + 1);
      error2 += e.dot(mass * e);
      norm2 += reference.col(n + 1).dot(mass * reference.col(n + 1));
    }
  }
  row.steps_per_s = wall.empty() ? 0.0 : 1.0 / median(wall);
  row.newton_per_step = row.completed > 0 ? static_cast<double>(newton_total) / row.completed : 0.0;
  row.trajectory_error = norm2 > 0.0 ? std::sqrt(error2 / norm2) : std::nan("");
  if (row.message.empty()) row.message = "all steps converged";
  std::printf("  %-12s %-10s r = %4d: %d/%d steps, E last %.4g (largest %.4g), min J %.3f, twist %.2f rad "
              "(largest %.2f), error %.3e, %.1f steps/s, %.2f Newton/step; %s\n",
              row.basis.c_str(), blend.c_str(), row.r, row.completed, t.steps, row.final_energy, row.largest_energy,
              row.smallest_volume_ratio, row.tip_angle, row.largest_tip_angle, row.trajectory_error, row.steps_per_s,
              row.newton_per_step, row.message.c_str());
  std::fflush(stdout);
  return row;
}

int run_twist(const TwistSettings& t, const std::string& out) {
  bench::Cantilever bar;
  bar.mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 0.5, 0.5), t.along, t.across, t.across);
  const int m = bar.mesh.num_elements();
  bar.model = std::make_unique<Model>(3 * bar.mesh.num_vertices());
  const int youngs = bar.model->parameter_layout().add("youngs_modulus", m);
  const int poisson = bar.model->parameter_layout().add("poisson_ratio", m);
  const MaterialKind material = t.material == "neo_hookean" ? MaterialKind::neo_hookean : MaterialKind::stvk;
  bar.model->add(std::make_unique<ElasticTerm<3>>(bar.mesh, make_material<3>(material), youngs, poisson));
  bar.rest.resize(3 * bar.mesh.num_vertices());
  for (int v = 0; v < bar.mesh.num_vertices(); ++v) {
    bar.rest.segment<3>(3 * v) = bar.mesh.rest_positions.row(v).transpose();
    if (bar.mesh.rest_positions(v, 0) < 1e-9)
      for (int k = 0; k < 3; ++k) bar.fixed_dofs.push_back(3 * v + k);
    if (bar.mesh.rest_positions(v, 0) > 4 - 1e-9) bar.tip_vertices.push_back(v);
  }
  bar.model->set_elimination(Elimination::dirichlet(bar.fixed_dofs, bar.rest));
  const Vector p = bench::cantilever_parameters(bar, 1e6, kPoisson);
  const SparseMatrix mass = mass_matrix(bar.mesh, Eigen::VectorXd::Constant(m, 100.0), MassLumping::consistent);
  Vector torque = Vector::Zero(bar.rest.size());
  const bool distributed = t.load == "distributed";
  const Vector vertex_mass = vertex_masses(mass);
  std::vector<int> loaded = bar.tip_vertices;
  if (distributed) {
    loaded.clear();
    for (int v = 0; v < bar.mesh.num_vertices(); ++v) loaded.push_back(v);
  }
  double r2 = 0.0;
  for (int v : loaded)
    r2 += (distributed ? vertex_mass[v] : 1.0) *
          (bar.mesh.rest_positions.row(v).tail<2>() - Eigen::RowVector2d(0.25, 0.25)).squaredNorm();
  for (int v : loaded) {
    const double weight = distributed ? vertex_mass[v] : 1.0;
    const Eigen::Vector2d r = bar.mesh.rest_positions.row(v).tail<2>().transpose() - Eigen::Vector2d(0.25, 0.25);
    torque[3 * v + 1] = -t.torque * weight * r.y() / r2;
    torque[3 * v + 2] = t.torque * weight * r.x() / r2;
  }
  for (int v = 0; v < bar.mesh.num_vertices(); ++v) torque[3 * v + 2] -= t.bend * vertex_mass[v];
  for (int dof : bar.fixed_dofs) torque[dof] = 0.0;
  std::printf("tailor %s, twisted %s bar: %d tets, %s torque %g, bend %g, %d Newmark steps of %g s (full space: %d of "
              "h / %d each), r = %d, %d domains%s\n",
              version_string, t.material.c_str(), m, t.load.c_str(), t.torque, t.bend, t.steps, t.time_step,
              t.reference_substeps, t.reference_substeps, t.size, t.domains,
              t.rigid_columns ? ", rigid columns per overlapping domain" : "");
  Matrix reference;
  std::vector<TwistRow> rows;
  rows.push_back(twist_run("full", "no", bar, p, mass, torque, t, reference, &reference));
  reference.conservativeResize(Eigen::NoChange, rows.front().completed + 1);  // errors over the full run's steps
  std::vector<std::string> blends = {"no"};
  blends.insert(blends.end(), t.blends.begin(), t.blends.end());
  for (const std::string& kind : t.bases)
    for (const std::string& blend : blends)  // one domain: every blend is its one rotation
      if (kind != "global" || blend == blends[std::min<std::size_t>(1, blends.size() - 1)] || blend == "no")
        rows.push_back(twist_run(kind, blend, bar, p, mass, torque, t, reference, nullptr));
  std::printf("\n%-12s %-10s %5s %7s %12s %12s %7s %8s %11s %9s %8s\n", "basis", "rotations", "r", "steps", "E last",
              "E largest", "min J", "twist", "traj. error", "steps/s", "Newton");
  for (const TwistRow& row : rows)
    std::printf("%-12s %-10s %5d %4d/%-2d %12.4g %12.4g %7.3f %8.2f %11.3e %9.1f %8.2f\n", row.basis.c_str(),
                row.blend.c_str(), row.r, row.completed, t.steps, row.final_energy, row.largest_energy,
                row.smallest_volume_ratio, row.tip_angle, row.trajectory_error, row.steps_per_s, row.newton_per_step);
  bench::Json json = bench::report("domain_reduction_twist");
  json["tets"] = m;
  json["torque"] = t.torque;
  json["load"] = t.load;
  json["material"] = t.material;
  json["bend"] = t.bend;
  json["steps"] = t.steps;
  json["time_step"] = t.time_step;
  json["interface_modes"] = t.interface_modes;
  json["fixed_interface_modes"] = t.fixed_interface_modes;
  json["domains"] = t.domains;
  json["size"] = t.size;
  json["newton_iterations"] = t.newton_iterations;
  json["rigid_columns"] = t.rigid_columns;
  json["reference_substeps"] = t.reference_substeps;
  bench::Json results = bench::Json::array();
  for (const TwistRow& r : rows)
    results.push_back({{"basis", r.basis},
                       {"rotations", r.rotations},
                       {"blend", r.blend},
                       {"r", r.r},
                       {"completed_steps", r.completed},
                       {"final_energy", r.final_energy},
                       {"largest_energy", r.largest_energy},
                       {"smallest_volume_ratio", r.smallest_volume_ratio},
                       {"twist_angle", r.tip_angle},
                       {"largest_twist_angle", r.largest_tip_angle},
                       {"trajectory_error", r.trajectory_error},
                       {"precompute_s", r.precompute_s},
                       {"steps_per_s", r.steps_per_s},
                       {"newton_per_step", r.newton_per_step},
                       {"message", r.message}});
  json["results"] = results;
  return bench::write_report(out, json, "domain_reduction_bench") ? 0 : 1;
}

}  // namespace

int run(int argc, char** argv) {
  Settings s;
  int tets = 64000;
  std::vector<std::string> bases = {"global", "domains", "overlapping"};
  std::string out = "bench_domain_reduction.json";
  bench::Cli cli("domain_reduction_bench",
                 "Global, domain-decomposed and overlapping-domain reduced dynamics at equal size: speed and error.");
  cli.tets(tets);
  cli.steps(s.steps);
  cli.integer("--size", s.size, "reduced size r of the global and overlapping bases", 1);
  cli.integer("--domains", s.domains, "METIS domains", 1);
  cli.integer("--fixed-interface-modes", s.fixed_interface_modes, "per domain", 0);
  cli.integer("--derivative-modes", s.derivative_modes, "per domain: local derivatives of this many modes", 0);
  cli.integer("--boundary-derivative-modes", s.boundary_derivative_modes,
              "per domain: local derivatives of this many boundary-driven modes", 0);
  cli.integer("--interface-modes", s.interface_modes, "interface traces of global modes", 1);
  cli.integer("--overlap-layers", s.overlap_layers, "element rings around each overlapping domain", 0);
  cli.number("--youngs", s.youngs, "Young's modulus", 0.0);
  cli.flag("--no-reference", [&] { s.reference = false; }, "skip the full-space run (no errors reported)");
  cli.choices("--bases", bases, "bases to run", {"global", "domains", "overlapping"});
  TwistSettings twist;
  cli.number("--twist", twist.torque, "run the twisted-bar case with this end torque instead (rotations off / on)",
             0.0);
  cli.integer("--twist-cells", twist.along, "twisted bar: cells along (3 x 3 across)", 1);
  cli.integer("--twist-steps", twist.steps, "twisted bar: Newmark steps", 1);
  cli.integer("--twist-size", twist.size, "twisted bar: r of the global basis (overlapping: r / domains per domain)", 1);
  cli.integer("--twist-domains", twist.domains, "twisted bar: METIS domains", 1);
  cli.integer("--twist-interface-modes", twist.interface_modes,
              "twisted bar: interface excitations of the domain basis (0: every interface DOF)", 0);
  cli.integer("--twist-fixed-interface-modes", twist.fixed_interface_modes, "twisted bar: per domain", 0);
  cli.number("--twist-time-step", twist.time_step, "twisted bar: Newmark time step h", 0.0);
  cli.choice("--twist-load", twist.load, "twisted bar: torque on the end face or distributed over the bar",
              {"end", "distributed"});
  cli.choice("--twist-material", twist.material, "twisted bar: material", {"stvk", "neo_hookean"});
  cli.number("--twist-bend", twist.bend, "twisted bar: transverse dead body load per unit mass (-z)", 0.0);
  cli.integer("--twist-newton-iterations", twist.newton_iterations, "twisted bar: Newton iterations per step", 1);
  cli.integer("--twist-reference-substeps", twist.reference_substeps,
              "twisted bar: full space steps h / k, k times per step (a reference at a finer step)", 1);
  cli.flag("--twist-rigid-columns", [&] { twist.rigid_columns = true; },
           "twisted bar: overlapping domains get their six rigid motions among their columns");
  cli.choices("--twist-bases", twist.bases, "twisted bar: bases run besides full space",
              {"global", "domains", "overlapping"});
  cli.choices("--twist-blends", twist.blends, "twisted bar: rotation blends of the rows with rotations",
              {"linear", "quaternion", "nearest"});
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  if (twist.torque > 0.0) return run_twist(twist, out);
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
  const bench::CantileverCells cells = bench::cantilever_cells(tets, kLength);
  Scene scene{bench::make_cantilever(kLength, cells, MaterialKind::stvk), {}, {}, {}};
  const int m = scene.elastic.mesh.num_elements();
  scene.p = bench::cantilever_parameters(scene.elastic, s.youngs, kPoisson);
  scene.mass = mass_matrix(scene.elastic.mesh, Eigen::VectorXd::Constant(m, kDensity), MassLumping::consistent);
  Vector g = Vector::Zero(scene.elastic.rest.size());
  for (int v = 0; v < scene.elastic.mesh.num_vertices(); ++v) g[3 * v + 2] = -kGravity;
  scene.gravity_force = scene.mass * g;
  std::printf("tailor %s, local reduced models: %d tets, %d domains, r = %d, %d Newmark steps of %g s, %d threads\n",
              version_string, m, s.domains, s.size, s.steps, kStep, threads);
  std::fflush(stdout);
  double full_step_s = 0.0;
  auto t = Clock::now();
  Matrix reference;
  if (s.reference) {
    reference = full_space_reference(cells, s, full_step_s);
    std::printf("  full space: %.2f s, median step %.3f s, tip fall %.3f\n", seconds_since(t), full_step_s,
                -tip_point(reference.col(s.steps), scene.elastic.tip_vertices).z());
  }
  t = Clock::now();
  const Eigen::VectorXi domains = partition_elements(scene.elastic.mesh, s.domains);
  const double partition_s = seconds_since(t);
  std::vector<Row> rows;
  for (const std::string& kind : bases) rows.push_back(run_basis(kind, scene, s, domains, reference));

  std::printf("\n%-12s %4s %-17s %7s %12s %9s %9s %9s %9s %13s %11s %9s %11s\n", "basis", "r", "energy", "groups",
              "precompute s", "(CPU s)", "steps/s", "(CPU)", "Newton", "traj. error", "tip error", "steps", "load");
  for (const Row& row : rows)
    std::printf("%-12s %4d %-17s %7d %12.1f %9.1f %9.1f %9.1f %9.2f %13.3e %11.4f %5d/%d %5.1f-%.1f\n",
                row.basis.c_str(), row.r, row.energy.c_str(), row.groups, row.precompute_s, row.precompute_cpu_s,
                row.steps_per_s, row.step_cpu_s > 0 ? 1.0 / row.step_cpu_s : 0.0, row.newton_per_step,
                row.trajectory_error, row.peak_tip_error, row.completed, s.steps, row.load_before, row.load_after);
  std::printf("(%d tets, METIS partition %.2f s; full-space median step %.3f s; steps/s: median wall time per step)\n",
              m, partition_s, full_step_s);

  bench::Json json = bench::report("domain_reduction");
  json["openmp_threads"] = threads;
  json["hardware_threads"] = std::thread::hardware_concurrency();
  json["tets"] = m;
  json["domains"] = s.domains;
  json["size"] = s.size;
  json["steps"] = s.steps;
  json["time_step"] = kStep;
  json["youngs_modulus"] = s.youngs;
  json["partition_s"] = partition_s;
  json["load_at_end"] = load_average();
  json["full_space_step_s"] = full_step_s;
  json["reference"] = s.reference;
  bench::Json results = bench::Json::array();
  for (const Row& r : rows) {
    bench::Json phases = bench::Json::array();
    for (const PhaseTiming& ph : r.phases) phases.push_back({{"phase", ph.name}, {"wall_s", ph.wall_s}, {"cpu_s", ph.cpu_s}});
    results.push_back({{"basis", r.basis},
                       {"r", r.r},
                       {"energy", r.energy},
                       {"groups", r.groups},
                       {"largest_group", r.largest_group},
                       {"coefficient_mb", r.coefficient_mb},
                       {"precompute_s", r.precompute_s},
                       {"precompute_cpu_s", r.precompute_cpu_s},
                       {"precompute_phases", phases},
                       {"steps_per_s", r.steps_per_s},
                       {"step_wall_s", r.step_wall_s},
                       {"step_cpu_s", r.step_cpu_s},
                       {"evaluate_wall_s_per_step", r.evaluate_wall_s},
                       {"evaluate_cpu_s_per_step", r.evaluate_cpu_s},
                       {"evaluations_per_step", r.evaluations_per_step},
                       {"load_before", r.load_before},
                       {"load_after", r.load_after},
                       {"newton_per_step", r.newton_per_step},
                       {"trajectory_error", r.trajectory_error},
                       {"peak_tip_error", r.peak_tip_error},
                       {"completed_steps", r.completed},
                       {"message", r.message}});
  }
  json["results"] = results;
  return bench::write_report(out, json, "domain_reduction_bench") ? 0 : 1;
}

}  // namespace tailor::bench::domain_reduction_bench
