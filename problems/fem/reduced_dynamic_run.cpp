// simulate_reduced_dynamic_scene (problems/fem/reduced_dynamic_run.hpp): the basis of
// dynamics.reduction, its reduced energy, and the steps of ReducedDynamics (or, with
// "rotations": "domains", of RotatingSubspaceDynamics) written as full-space frames.
#include "problems/fem/reduced_dynamic_run.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <stdexcept>

#include "forward/core/timing.hpp"
#include "forward/fem/loads.hpp"
#include "forward/fem/mass.hpp"
#include "forward/fem/material.hpp"
#include "forward/reduction/domain_decomposition.hpp"
#include "forward/reduction/domain_partition.hpp"
#include "forward/reduction/domain_rotations.hpp"
#include "forward/reduction/free_stiffness_factor.hpp"
#include "forward/reduction/krylov_recurrence.hpp"
#include "forward/reduction/local_reduced_stvk.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/reduction/modal_derivatives.hpp"
#include "forward/reduction/overlapping_domains.hpp"
#include "forward/reduction/projected_reduced_model.hpp"
#include "forward/reduction/reduced_dynamics.hpp"
#include "forward/reduction/rotating_subspace_dynamics.hpp"
#include "problems/fem/physics_warnings.hpp"
#include "problems/output_process.hpp"
#include "problems/scene_error.hpp"

namespace tailor {
namespace {

// Above this many columns the auto energy of a global basis is the projected model: its
// polynomial is an (r + r(r+1)/2)^2 matrix (0.2 GB at r = 100, 1 GB at r = 150).
constexpr int kLargestGlobalPolynomial = 60;

[[noreturn]] void reduction_fail(const Scene& scene, const std::string& key, const std::string& what) {
  throw SceneError(scene.source + ": " + key + ": " + what);
}

struct ReducedScene {
  std::unique_ptr<Model> elastic;  // the materials alone (loads are projected forces)
  Vector x0, p0, loads;            // rest state, moduli, every load at full strength (gravity included)
  SparseMatrix mass;               // the scene's lumping
  bool nonlinear = false, stvk = true;
};

// The global candidates: the loads' static response, the lowest vibration modes and, for
// nonlinear materials, blocks 2..k of the Krylov recurrence of the lowest modes and the response
// (k = 2: the modal derivatives). M-orthonormal, near-duplicates dropped.
Matrix global_basis(const DynamicReductionSpec& spec, const ReducedScene& s, int dim) {
  const Eigen::Index n = s.x0.size();
  std::vector<Matrix> blocks;
  Matrix responses(n, 0);
  if (spec.static_responses && s.loads.norm() > 0.0) {
    const FreeStiffnessFactor stiffness(*s.elastic, s.x0, s.p0);
    responses = stiffness.solve(Matrix(s.loads));
    blocks.push_back(responses);
  }
  ModalAnalysisOptions modal;
  modal.count = spec.displacement_modes;
  const ModalAnalysis modes = modal_analysis(*s.elastic, dim, s.x0, s.p0, s.mass, modal);
  blocks.push_back(modes.modes);
  const Eigen::Index k = std::min<Eigen::Index>(spec.derivative_modes, modes.modes.cols());
  if (s.nonlinear && spec.krylov_order >= 2 && k + responses.cols() > 0) {
    Matrix seeds(n, k + responses.cols());
    seeds.leftCols(k) = modes.modes.leftCols(k);
    // Scaled like the modes (M-norm 1) so that the finite-difference step of the derivatives fits.
    for (Eigen::Index c = 0; c < responses.cols(); ++c)
      seeds.col(k + c) = responses.col(c) / std::sqrt(responses.col(c).dot(s.mass * responses.col(c)));
    if (spec.krylov_order == 2) {
      blocks.push_back(modal_derivatives(*s.elastic, s.x0, s.p0, seeds));
    } else {
      KrylovRecurrenceOptions krylov;
      krylov.order = spec.krylov_order;
      const KrylovRecurrence recurrence = krylov_recurrence(*s.elastic, s.x0, s.p0, s.mass, seeds, krylov);
      for (std::size_t j = 1; j < recurrence.blocks.size(); ++j) blocks.push_back(recurrence.blocks[j]);
    }
  }
  Eigen::Index columns = 0;
  for (const Matrix& b : blocks) columns += b.cols();
  Matrix candidates(n, columns);
  columns = 0;
  for (const Matrix& b : blocks) {
    candidates.middleCols(columns, b.cols()) = b;
    columns += b.cols();
  }
  return mass_orthonormal_basis(candidates, s.mass, 1e-6);
}

// The basis of dynamics.reduction.basis (docs/reduction.md, "Local reduced models"), and the
// domains' vertex weights (num_vertices x domains; empty for the global basis): the overlap weights
// or, for a partition, each vertex's volume fraction per domain.
Matrix reduced_basis(const DynamicReductionSpec& spec, const ReducedScene& s, const Mesh& mesh, int& domains,
                     Matrix& weights) {
  domains = 0;
  weights.resize(0, 0);
  if (spec.basis == "global") return global_basis(spec, s, mesh.dim());
  const DynamicDomainsSpec& d = spec.domains;
  const Eigen::VectorXi element_domain = d.from_regions ? domains_from_regions(mesh) : partition_elements(mesh, d.count);
  domains = domain_count(element_domain);
  if (spec.basis == "overlapping") {
    OverlappingDomainOptions options;
    options.overlap_layers = d.overlap_layers;
    const OverlappingDomains od = overlapping_domains(*s.elastic, mesh, s.x0, s.p0, s.mass, element_domain, options);
    weights = od.weights;
    return mass_orthonormal_basis(blended_basis(od.weights, global_basis(spec, s, mesh.dim()), mesh.dim()), s.mass,
                                  1e-8);
  }
  DomainDecompositionOptions options;
  options.fixed_interface_modes = d.fixed_interface_modes;
  options.interface_modes = d.interface_modes;
  // A linear material has no derivatives (their finite differences would be round-off).
  options.derivative_modes = s.nonlinear ? d.derivative_modes : 0;
  options.boundary_derivative_modes = s.nonlinear ? d.boundary_derivative_modes : 0;
  if (s.loads.norm() > 0.0) options.loads = Matrix(s.loads);  // interior static responses (Craig-Bampton)
  weights = domain_vertex_weights(mesh, element_domain);
  return domain_decomposition(*s.elastic, mesh, s.x0, s.p0, s.mass, element_domain, options).basis;
}

}  // namespace

DynamicRun simulate_reduced_dynamic_scene(const Scene& scene, const std::string& out_dir, std::ostream* log) {
  const auto t_start = Clock::now();
  const DynamicsSpec& spec = *scene.dynamics;
  const DynamicReductionSpec& reduction = *spec.reduction;
  if (spec.scheme == TimeScheme::bdf2)
    reduction_fail(scene, "dynamics.scheme",
                   "\"bdf2\" is not offered with " + reduction.key + " (\"implicit_euler\" or \"newmark\")");
  if (spec.solver_method != "newton")
    reduction_fail(scene, "dynamics.solver.method",
                   "the reduced steps are solved by dense Newton in q; \"descent\" is for full-space steps");
  DynamicSceneModel d = build_dynamic_scene(scene);
  const StaticSetup& setup = d.setup;
  const Mesh& mesh = setup.mesh;
  require_supported(scene, setup);
  if (setup.prescribed_displacement.norm() > 0.0)
    reduction_fail(scene, reduction.key,
                   "needs supports that hold their vertices at rest (a prescribed displacement is not in a "
                   "displacement basis)");

  ReducedScene s;
  {
    StaticSetup materials_only = setup;
    materials_only.has_loads = false;
    s.elastic = build_static_model(materials_only, 1.0);
  }
  s.x0 = setup.rest_state();
  s.p0 = setup.parameters();
  s.mass = mass_matrix(mesh, setup.density, spec.lumping);
  s.loads = setup.nodal_forces;  // gravity was taken out of them by build_dynamic_scene
  if (scene.loads.gravity) s.loads += gravity_forces(mesh, setup.density, *scene.loads.gravity);
  for (const MaterialBlock& b : setup.materials) {
    s.nonlinear = s.nonlinear || b.spline_curves || !make_material<3>(b.kind)->tangent_is_constant();
    s.stvk = s.stvk && !b.spline_curves && b.kind == MaterialKind::stvk;
  }
  const bool rotating = reduction.rotations == "domains";
  if (rotating && spec.scheme != TimeScheme::newmark)
    reduction_fail(scene, "dynamics.scheme",
                   "\"rotations\": \"domains\" steps with Newmark only (the turning subspace's incremental "
                   "potential); use \"newmark\"");
  if (rotating && mesh.dim() != 3)
    reduction_fail(scene, reduction.key + ".rotations", "per-domain rotations need a 3D mesh");
  if (reduction.energy == "polynomial" && !s.stvk)
    reduction_fail(scene, reduction.key + ".energy",
                   "\"polynomial\" needs every material to be \"stvk\" (the exact reduced polynomial); use "
                   "\"projected\" or \"auto\"");

  DynamicRun run;
  ReducedRunSummary summary;
  summary.basis = reduction.basis;
  summary.rotations = reduction.rotations;
  if (rotating) summary.rotation_blend = reduction.rotation_blend;
  auto t = Clock::now();
  Matrix basis, weights;
  try {
    basis = reduced_basis(reduction, s, mesh, summary.domains, weights);
  } catch (const std::exception& e) {  // bad counts for this mesh, a domain not held, a failed eigen solve
    reduction_fail(scene, reduction.key, std::string("the reduced basis cannot be built: ") + e.what());
  }
  summary.basis_seconds = seconds_since(t);
  summary.r = static_cast<int>(basis.cols());
  const bool polynomial =
      !rotating &&
      (reduction.energy == "polynomial" ||
       (reduction.energy == "auto" && s.stvk && (reduction.basis != "global" || summary.r <= kLargestGlobalPolynomial)));
  summary.energy = polynomial ? "polynomial" : "projected";
  t = Clock::now();
  if (summary.r < 1) reduction_fail(scene, reduction.key, "the reduced basis is empty (every column was dropped)");
  std::unique_ptr<ReducedElasticModel> energy;
  try {
    if (rotating) {
      // No reduced energy: the turning basis is evaluated on the mesh in every step.
    } else if (polynomial) {
      auto local =
          std::make_unique<LocalReducedStvk>(*s.elastic, mesh, s.p0, basis, 1e-14 * basis.cwiseAbs().maxCoeff());
      summary.groups = local->groups();
      summary.largest_group = local->largest_group();
      energy = std::move(local);
    } else {
      energy = std::make_unique<ProjectedReducedModel>(*s.elastic, s.p0, s.x0, basis);
    }
  } catch (const std::invalid_argument& e) {  // a material term the polynomial cannot take
    reduction_fail(scene, reduction.key + ".energy", e.what());
  }
  summary.energy_seconds = seconds_since(t);

  ReducedDynamicsOptions options;
  options.integrator = spec.scheme == TimeScheme::newmark ? ReducedIntegrator::newmark : ReducedIntegrator::implicit_euler;
  options.time_step = spec.time_step;
  options.rayleigh_mass = spec.rayleigh_alpha;
  options.rayleigh_stiffness = spec.rayleigh_beta;
  options.max_newton_iterations = std::max(setup.solver.newton.max_iterations, 30);
  options.newton_tolerance = 1e-10;
  const Vector load = basis.transpose() * s.loads;
  std::unique_ptr<ReducedDynamics> dynamics;
  std::unique_ptr<RotatingSubspaceDynamics> turning;
  if (rotating) {
    RotatingSubspaceOptions r;
    r.time_step = spec.time_step;
    r.rayleigh_mass = spec.rayleigh_alpha;
    r.rayleigh_stiffness = spec.rayleigh_beta;
    r.blend = reduction.rotation_blend == "linear"    ? RotationBlend::linear
              : reduction.rotation_blend == "nearest" ? RotationBlend::nearest
                                                      : RotationBlend::quaternion;
    r.max_newton_iterations = options.max_newton_iterations;
    r.newton_tolerance = options.newton_tolerance;
    try {
      turning = std::make_unique<RotatingSubspaceDynamics>(*s.elastic, mesh, s.p0, s.x0, s.mass, s.loads, basis,
                                                           weights, r);
    } catch (const std::invalid_argument& e) {
      reduction_fail(scene, reduction.key + ".rotations", e.what());
    }
  } else {
    dynamics = std::make_unique<ReducedDynamics>(*energy, options, Matrix(), load);
  }
  // The full-space report's potential is every term but inertia and damping (elastic, loads,
  // gravity); the loads' terms at rest are a constant the reduced W(q) - f_q^T q lacks.
  double potential_at_rest = 0.0;
  for (const auto& term : d.model->terms())
    if (term.get() != d.terms.inertia && term.get() != d.terms.damping)
      potential_at_rest += term->value(d.initial_positions, d.p);
  Vector v0 = d.initial_velocities;
  for (int dof : setup.fixed_dofs) v0[dof] = 0.0;
  // One of the two states is stepped: q (fixed basis) or the full-space state of the turning one.
  ReducedState state;
  SubspaceState turned;
  if (turning)
    turned = turning->initial_state(v0);
  else
    state = dynamics->initial_state(Vector::Zero(summary.r), project_to_basis(basis, s.mass, v0));
  run.reduction = summary;
  run.timings.setup = seconds_since(t_start);
  if (log)
    *log << "reduced dynamic scene '" << scene.name << "': " << mesh.num_elements() << " elements, "
         << d.model->elimination().num_free() << " free DOFs; basis \"" << summary.basis << "\", r = " << summary.r
         << ", " << summary.energy << " energy (precomputation " << std::setprecision(3)
         << summary.basis_seconds + summary.energy_seconds << std::defaultfloat << " s); " << to_string(spec.scheme)
         << ", h = " << spec.time_step << ", " << spec.steps << " steps\n";

  run.warnings = locking_warnings(scene);
  for (const std::string& warning : time_step_warnings(scene)) {
    if (log) *log << "warning: " << warning << "\n";
    run.warnings.push_back(warning);
  }
  const bool writes = writes_output();
  const std::filesystem::path out(out_dir), frames = out / "frames";
  if (writes) {
    std::error_code error;
    std::filesystem::create_directories(frames, error);
    if (error)
      throw std::runtime_error("cannot create the output folder '" + frames.string() + "': " + error.message());
  }
  DynamicState full;  // the frame of a reduced state: x = x0 + Phi q, v = Phi q'
  auto write_frame = [&](int step) {
    const auto t0 = Clock::now();
    full.step = step;
    full.time = step * spec.time_step;
    full.x = d.initial_positions + (turning ? turned.u : Vector(basis * state.q));
    full.v = turning ? turned.v : Vector(basis * state.v);
    run.frames.emplace_back(full.time, writes ? write_dynamic_frame(frames, setup, d.rest, full) : std::string());
    run.timings.output += seconds_since(t0);
  };
  auto record = [&](int step, double residual, int iterations, double seconds) {
    if (turning) {
      const double kinetic = 0.5 * turned.v.dot(s.mass * turned.v);
      const double potential = turning->total_energy(turned) - kinetic + potential_at_rest;
      run.records.push_back({step, step * spec.time_step, kinetic, potential, seconds, residual, iterations});
      return;
    }
    const double kinetic = 0.5 * state.v.squaredNorm();  // M_q = I
    const double potential = energy->energy(state.q) - load.dot(state.q) + potential_at_rest;
    run.records.push_back({step, step * spec.time_step, kinetic, potential, seconds, residual, iterations});
  };
  record(0, 0.0, 0, 0.0);
  write_frame(0);
  run.completed = true;
  run.message = "all steps converged";
  for (int n = 0; n < spec.steps; ++n) {
    const auto t0 = Clock::now();
    ReducedState next;
    SubspaceState turned_next;
    int iterations = 0;
    std::string message;
    const bool ok = turning ? turning->step(turned, turned_next, iterations, message)
                            : dynamics->step(state, next, iterations, message) && next.q.allFinite();
    if (!ok) {
      run.completed = false;
      run.message = "step " + std::to_string(n + 1) + " failed: " + (message.empty() ? "not finite" : message);
      break;
    }
    if (turning)
      turned = std::move(turned_next);
    else
      state = std::move(next);
    const int step = n + 1;
    record(step, std::nan(""), iterations, seconds_since(t0));  // not measured: null
    run.steps_done = step;
    if (step % spec.output_every == 0 || step == spec.steps) write_frame(step);
    if (log && (step % std::max(1, spec.steps / 10) == 0 || step == spec.steps))
      *log << "  step " << step << "/" << spec.steps << "  t " << step * spec.time_step << "  Newton " << iterations
           << "  E " << std::scientific << std::setprecision(4)
           << run.records.back().kinetic + run.records.back().potential << std::defaultfloat << "\n";
  }
  run.series_path = (out / "result.pvd").string();
  if (writes) write_dynamic_series(run.series_path, run);
  run.report_path = (out / "report.json").string();
  run.timings.total = seconds_since(t_start);
  if (writes) write_dynamic_report_json(run.report_path, scene, run);
  if (log)
    *log << (run.completed ? "completed " : "FAILED: ") << run.message << "; wrote " << run.report_path << " and "
         << run.series_path << " (" << run.frames.size() << " frames)\n";
  return run;
}

}  // namespace tailor
