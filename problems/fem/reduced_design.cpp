#include "problems/fem/reduced_design.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <ostream>
#include <stdexcept>
#include <streambuf>

#include "forward/core/timing.hpp"
#include "forward/fem/mass.hpp"
#include "forward/fem/material_registry.hpp"
#include "forward/reduction/domain_decomposition.hpp"
#include "forward/reduction/domain_partition.hpp"
#include "forward/reduction/free_space.hpp"
#include "forward/reduction/krylov_recurrence.hpp"
#include "forward/reduction/overlapping_domains.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/material_modes.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/reduction/modal_derivatives.hpp"
#include "forward/reduction/polynomial_design_model.hpp"
#include "forward/reduction/reduced_stvk.hpp"
#include "forward/solve/sparse_cholesky.hpp"
#include "problems/fem/inverse_handles.hpp"
#include "problems/fem/inverse_scene.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/fem/scene_selection.hpp"
#include "problems/output_process.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"

namespace tailor {
namespace {

[[noreturn]] void scene_fail(const Scene& scene, const std::string& key, const std::string& what) {
  throw SceneError(scene.source + ": " + key + ": " + what);
}

// Solves with the free-space stiffness at rest: S K_y^-1 S^T rhs.
class RestStiffness {
 public:
  RestStiffness(const Model& model, const Vector& x, const Vector& p) : model_(model) {
    SparseMatrix upper = SparseMatrix(free_stiffness(model, x, p).triangularView<Eigen::Upper>());
    upper.makeCompressed();
    const FactorizationResult f = factor_.factorize(upper);
    if (!f.success || !f.positive_definite)
      throw std::runtime_error("reduced design: the stiffness at rest is not positive definite: " +
                               f.message);
  }
  Matrix solve(const Matrix& rhs) const {
    const SparseMatrix& s = model_.elimination().basis();
    return s * factor_.solve_columns(Matrix(s.transpose() * rhs));
  }

 private:
  const Model& model_;
  SparseCholesky factor_;
};

// Appends the milliseconds since the previous iteration row to every row the optimizer prints
// (rows start with the iteration number; the header gets "ms").
class MillisecondsColumn : public std::streambuf {
 public:
  explicit MillisecondsColumn(std::ostream& target) : target_(target), last_(Clock::now()) {}

 protected:
  int overflow(int c) override {
    if (c == traits_type::eof()) return 0;
    if (c != '\n') {
      line_.push_back(static_cast<char>(c));
      return c;
    }
    const auto first = line_.find_first_not_of(' ');
    char tail[32];
    if (first != std::string::npos && line_[first] >= '0' && line_[first] <= '9') {
      const auto now = Clock::now();
      std::snprintf(tail, sizeof tail, "  %9.2f", 1e3 * std::chrono::duration<double>(now - last_).count());
      last_ = now;
    } else {
      std::snprintf(tail, sizeof tail, "  %9s", "ms");
    }
    target_ << line_ << tail << '\n' << std::flush;
    line_.clear();
    return c;
  }

 private:
  std::ostream& target_;
  std::string line_;
  Clock::time_point last_;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The polynomial's coefficient width r + P (or r); 0 for a cubature model.
int coefficient_width(const ReducedEquilibriumFunctional& f) {
  const auto* polynomial = dynamic_cast<const PolynomialDesignModel*>(&f.model());
  return polynomial ? static_cast<int>(polynomial->base().rows()) : 0;
}

}  // namespace

Eigen::VectorXd ReducedDesign::youngs_modulus(const Vector& w) const {
  return setup.youngs_modulus.cwiseProduct((Vector::Ones(material_modes.rows()) + material_modes * w));
}

std::vector<double> ReducedDesign::handle_errors(const Vector& displacement) const {
  const int dim = setup.dim();
  std::vector<double> out;
  for (const ReducedDesignHandle& h : handles) {
    Vector mean = Vector::Zero(dim);
    for (int v : h.vertices) mean += displacement.segment(dim * v, dim);
    mean /= static_cast<double>(h.vertices.size());
    out.push_back((mean - h.target).norm() / h.target.norm());
  }
  return out;
}

namespace {

// Per observation row (handle h, component k): ubar_h[k] and the weight W_h / |ubar_h|^2.
void observation_targets(const ReducedDesign& design, Vector& target, Vector& weights) {
  const int dim = design.setup.dim();
  const Eigen::Index rows = dim * static_cast<Eigen::Index>(design.handles.size());
  target.resize(rows);
  weights.resize(rows);
  for (std::size_t h = 0; h < design.handles.size(); ++h) {
    const ReducedDesignHandle& handle = design.handles[h];
    for (int k = 0; k < dim; ++k) {
      const Eigen::Index row = dim * static_cast<Eigen::Index>(h) + k;
      target[row] = handle.target[k];
      weights[row] = handle.weight / handle.target.squaredNorm();
    }
  }
}

// The reduced coefficients and the functional for design.basis.
void precompute(ReducedDesign& design) {
  const StaticSetup& setup = design.setup;
  const Mesh& mesh = setup.mesh;
  const int dim = mesh.dim();
  const Model& model = *design.model;
  const Vector p0 = setup.parameters();
  const double volume = element_volumes(mesh).sum();
  const ReductionSpec& reduction = design.spec;
  ReducedEquilibriumData data;
  data.load = design.basis.transpose() * setup.nodal_forces;
  bool polynomial = !reduction.cubature;
  for (const MaterialBlock& b : setup.materials)
    polynomial = polynomial && !b.spline_curves && find_material(b.kind).traits.polynomial_in_deformation;
  auto t = Clock::now();
  if (polynomial) {
    // Reduced coefficients: G_0 at E0, G_j at E0 y_j.
    const int m = static_cast<int>(design.material_modes.cols());
    Matrix weights(mesh.num_elements(), m + 1);
    weights.col(0).setOnes();
    weights.rightCols(m) = design.material_modes;
    std::vector<Matrix> coefficients = reduced_stvk_coefficients(model, p0, design.basis, weights);
    design.timings.coefficients = seconds_since(t);
    data.base = std::move(coefficients[0]);
    data.modes.assign(std::make_move_iterator(coefficients.begin() + 1),
                      std::make_move_iterator(coefficients.end()));
    design.cubature.reset();
  } else {
    // No polynomial: a cubature rule over the base material and every mode (refitted on every
    // basis, since the rule integrates the forces of this basis).
    ReducedDesignCubature summary;
    data.model =
        fit_reduced_design_cubature(model, p0, design.basis, design.material_modes, data.load,
                                    reduction.cubature.value_or(CubatureSpec{}), reduction.key, summary);
    design.timings.cubature += seconds_since(t);
    design.cubature = summary;
  }
  // Observations: the mean displacement of each handle's vertices.
  const Eigen::Index rows = dim * static_cast<Eigen::Index>(design.handles.size());
  data.rows = Matrix::Zero(rows, design.basis.cols());
  for (std::size_t h = 0; h < design.handles.size(); ++h) {
    const ReducedDesignHandle& handle = design.handles[h];
    const double share = 1.0 / static_cast<double>(handle.vertices.size());
    for (int k = 0; k < dim; ++k) {
      const Eigen::Index row = dim * static_cast<Eigen::Index>(h) + k;
      for (int v : handle.vertices) data.rows.row(row) += share * design.basis.row(dim * v + k);
    }
  }
  observation_targets(design, data.target, data.row_weights);
  data.regularization = reduction.smoothness * design.material_eigenvalues.cwiseMax(0.0);  // lambda_1 ~ -eps
  data.element_modes = design.material_modes;
  data.element_weights = element_volumes(mesh) / volume;
  data.positivity_floor = reduction.min_relative_modulus;
  data.positivity_weight = reduction.positivity_weight;
  design.functional = std::make_unique<ReducedEquilibriumFunctional>(std::move(data));
}

}  // namespace

double refine_basis(ReducedDesign& design, const Vector& w, const Vector& displacement) {
  const auto t0 = Clock::now();
  const StaticSetup& setup = design.setup;
  const Model& model = *design.model;
  const int ne = setup.mesh.num_elements();
  const Vector x = setup.rest_state() + displacement;
  StaticSetup at_w = setup;
  at_w.youngs_modulus = design.youngs_modulus(w);
  const Vector p0 = setup.parameters(), pw = at_w.parameters();
  const int offset = model.parameter_layout().at("youngs_modulus").offset;
  // The gradient g(x, p) = F(x; E) - f is linear in E, F the internal force and f the loads:
  // F(x; E0 y_j) = g(x, p(E0 (y_j + c))) - c g(x, p0) + (1 - c) f.
  const Vector g0 = model.gradient(x, p0);
  const int m = design.num_design();
  Matrix rhs(setup.num_dofs(), m);
  for (int j = 0; j < m; ++j) {
    const double c = 1.0 - std::min(design.material_modes.col(j).minCoeff(), 0.0);
    Vector p = p0;
    p.segment(offset, ne) =
        setup.youngs_modulus.cwiseProduct((design.material_modes.col(j).array() + c).matrix());
    rhs.col(j) = -(model.gradient(x, p) - c * g0 + (1.0 - c) * setup.nodal_forces);
  }
  // du/dw_j = -K_t^-1 dF/dw_j at the design's full-space equilibrium.
  const RestStiffness tangent(model, x, pw);
  Matrix candidates(setup.num_dofs(), design.basis.cols() + 1 + m);
  candidates << design.basis, displacement, tangent.solve(rhs);
  design.basis_candidates += 1 + m;
  design.basis = mass_orthonormal_basis(candidates, design.mass, 1e-6);
  const double seconds = seconds_since(t0);
  precompute(design);
  design.timings.refinement += seconds;
  design.timings.total += seconds_since(t0);
  return seconds_since(t0);
}

namespace {

// The "domains" / "overlapping" basis of inverse.design.reduction.basis (docs/reduction.md,
// "Local reduced models"): Craig-Bampton per domain with the loads' interior responses, plus the
// global candidates' design responses kept through `global` (so the design sensitivities stay in
// the span); or the global basis blended by principal-direction weights.
Matrix local_basis(const ReductionSpec& reduction, const Model& model, const Mesh& mesh, const Vector& x0,
                   const Vector& p0, const SparseMatrix& mass, const Matrix& global, const Vector& nodal_forces,
                   const std::vector<Vector>& handle_loads) {
  const DomainBasisSpec& spec = reduction.domains;
  const Eigen::VectorXi domains = spec.from_regions ? domains_from_regions(mesh) : partition_elements(mesh, spec.count);
  if (reduction.basis == "overlapping") {
    OverlappingDomainOptions options;
    options.overlap_layers = spec.overlap_layers;
    const OverlappingDomains od = overlapping_domains(model, mesh, x0, p0, mass, domains, options);
    return mass_orthonormal_basis(blended_basis(od.weights, global, mesh.dim()), mass, 1e-6);
  }
  DomainDecompositionOptions options;
  options.fixed_interface_modes = spec.fixed_interface_modes;
  options.derivative_modes = spec.derivative_modes;
  options.interface_modes = spec.interface_modes;
  options.loads = Matrix(nodal_forces.size(), static_cast<Eigen::Index>(handle_loads.size()) + 1);
  for (std::size_t h = 0; h < handle_loads.size(); ++h) options.loads.col(static_cast<Eigen::Index>(h)) = handle_loads[h];
  options.loads.rightCols(1) = nodal_forces;
  const Matrix local = domain_decomposition(model, mesh, x0, p0, mass, domains, options).basis;
  Matrix all(local.rows(), local.cols() + global.cols());
  all << local, global;
  return mass_orthonormal_basis(all, mass, 1e-6);
}

}  // namespace

ReducedDesign build_reduced_design(const Scene& scene) {
  const auto t_begin = Clock::now();
  if (!scene.inverse || !scene.inverse->design.reduction)
    throw std::invalid_argument("build_reduced_design: the scene has no inverse.design.reduction");
  const InverseSpec& spec = *scene.inverse;
  const ReductionSpec& reduction = *spec.design.reduction;
  ReducedDesign design;
  design.scene_name = scene.name;
  design.scene_source = scene.source;
  design.spec = reduction;
  design.optimizer = spec.optimizer;

  // Objective: exactly one handles term; every handle with force and displacement.
  const HandlesTerm* term = nullptr;
  for (const ObjectiveTermSpec& t : spec.objective) {
    if (const auto* h = t.settings_as<HandlesTerm>()) {
      term = h;
      continue;
    }
    scene_fail(scene, t.key,
               "the reduced design loop (" + reduction.key + ") takes only a \"handles\" term; \"" +
                   t.type() + "\" is not supported there (regularize with " + reduction.key + ".smoothness)");
  }
  if (!term) scene_fail(scene, "inverse.objective", "the reduced design loop needs a \"handles\" term");

  require_linear_elements(scene, "the reduced design loop (" + reduction.key + ")");
  design.setup = setup_static_scene(scene);
  StaticSetup& setup = design.setup;
  const Mesh& mesh = setup.mesh;
  const int dim = mesh.dim();
  // Any material linear in Young's modulus (polynomial for StVK and linear, cubature for the
  // others); spline curves carry their moduli themselves.
  for (std::size_t b = 0; b < setup.materials.size(); ++b)
    if (setup.materials[b].spline_curves)
      throw std::invalid_argument(scene.source + ": " + reduction.key + ": materials[" + std::to_string(b) +
                                  "] is a spline material, whose curves carry the moduli: the reduced design "
                                  "loop designs Young's modulus, which it ignores");
  if (setup.prescribed_displacement.size() > 0 && setup.prescribed_displacement.cwiseAbs().maxCoeff() > 0.0)
    scene_fail(scene, "dirichlet",
               "the reduced design loop reduces about the rest shape: prescribed displacements must be zero");

  std::vector<bool> taken(static_cast<std::size_t>(mesh.num_vertices()), false);
  for (int d : setup.fixed_dofs) taken[static_cast<std::size_t>(d / dim)] = true;
  std::vector<Vector> handle_loads;
  for (const HandleSpec& h : term->handles) {
    if (!h.force || !h.displacement)
      scene_fail(
          scene, h.key,
          "the reduced design loop applies each handle's force and targets its displacement: give both "
          "\"force\" (or \"force_per_vertex\") and \"displacement\"");
    check_dimension(scene, mesh, *h.displacement, h.key + ".displacement");
    check_dimension(scene, mesh, *h.force, h.key + (h.force_per_vertex ? ".force_per_vertex" : ".force"));
    if (!(h.displacement->norm() > 0.0)) scene_fail(scene, h.key + ".displacement", "must not be zero");
    ReducedDesignHandle handle;
    handle.key = h.key;
    handle.vertices = select_vertices(scene, mesh, h.vertices);
    handle.target = *h.displacement;
    handle.weight = h.weight;
    const double n = static_cast<double>(handle.vertices.size());
    handle.force = h.force_per_vertex ? Vector(n * *h.force) : *h.force;
    Vector load = Vector::Zero(setup.num_dofs());
    for (int v : handle.vertices) {
      if (taken[static_cast<std::size_t>(v)])
        scene_fail(scene, h.key + ".vertices",
                   "vertex " + std::to_string(v) + " is also in another handle or a dirichlet condition");
      taken[static_cast<std::size_t>(v)] = true;
      load.segment(dim * v, dim) = handle.force / n;
    }
    setup.nodal_forces += load;
    setup.has_loads = true;
    handle_loads.push_back(std::move(load));
    design.handles.push_back(std::move(handle));
  }
  require_supported(scene, setup);
  design.model = build_static_model(setup, 1.0);
  const Model& model = *design.model;
  const Vector x0 = setup.rest_state(), p0 = setup.parameters();
  Eigen::VectorXd density = setup.density;
  if (!(density.minCoeff() > 0.0)) density.setOnes();  // only the inner product of the basis
  const SparseMatrix mass = mass_matrix(mesh, density, MassLumping::consistent);
  design.timings.setup = seconds_since(t_begin);

  // Candidate displacement vectors, most important first.
  std::vector<Matrix> blocks;
  auto t = Clock::now();
  const RestStiffness stiffness(model, x0, p0);
  Matrix responses(setup.num_dofs(), 0);
  const Vector other_loads = setup.nodal_forces - [&] {
    Vector s = Vector::Zero(setup.num_dofs());
    for (const Vector& l : handle_loads) s += l;
    return s;
  }();
  {
    Matrix rhs(setup.num_dofs(), static_cast<Eigen::Index>(handle_loads.size()) + 1);
    for (std::size_t h = 0; h < handle_loads.size(); ++h)
      rhs.col(static_cast<Eigen::Index>(h)) = handle_loads[h];
    rhs.col(rhs.cols() - 1) = other_loads;
    if (other_loads.norm() == 0.0) rhs.conservativeResize(Eigen::NoChange, rhs.cols() - 1);
    responses = stiffness.solve(rhs);
  }
  const Vector u0 = stiffness.solve(Matrix(setup.nodal_forces)).col(0);
  if (reduction.static_responses) blocks.push_back(responses);
  design.timings.responses = seconds_since(t);

  t = Clock::now();
  ModalAnalysisOptions modal_options;
  modal_options.count = reduction.displacement_modes;
  const ModalAnalysis modes = modal_analysis(model, dim, x0, p0, mass, modal_options);
  blocks.push_back(modes.modes);
  design.timings.displacement_modes = seconds_since(t);

  t = Clock::now();
  MaterialModeOptions material_options;
  material_options.weighting = spec.design.mode_weighting;
  MaterialModes material = material_modes(mesh, *spec.design.modes, material_options);
  const double volume = element_volumes(mesh).sum();
  design.material_modes = std::sqrt(volume) * material.modes;
  for (Eigen::Index j = 0; j < design.material_modes.cols(); ++j)  // a sign convention: sum_e y_je >= 0
    if (design.material_modes.col(j).sum() < 0.0) design.material_modes.col(j) *= -1.0;
  design.material_eigenvalues = material.eigenvalues;
  design.timings.material_modes = seconds_since(t);

  if (reduction.design_responses) {
    t = Clock::now();
    const int offset = model.parameter_layout().at("youngs_modulus").offset;
    const int m = static_cast<int>(design.material_modes.cols());
    Matrix rhs(setup.num_dofs(), m);
    // K is linear in E, and materials take only E > 0: K(E0 y_j) u0 = K(E0 (y_j + c)) u0 - K(E0 c) u0
    // with the shift c = 1 - min(y_j).
    const Vector k_u0 = model.hessian_times(x0, p0, u0);
    for (int j = 0; j < m; ++j) {
      const double c = 1.0 - std::min(design.material_modes.col(j).minCoeff(), 0.0);
      Vector p = p0;
      p.segment(offset, mesh.num_elements()) =
          setup.youngs_modulus.cwiseProduct((design.material_modes.col(j).array() + c).matrix());
      rhs.col(j) = -(model.hessian_times(x0, p, u0) - c * k_u0);
    }
    blocks.push_back(stiffness.solve(rhs));
    design.timings.responses += seconds_since(t);
  }

  // Modal derivatives for every nonlinear material (central differences of exact
  // Hessian-vector products, modal_derivatives.hpp); a linear material has none.
  bool any_nonlinear = false;
  for (const MaterialBlock& b : setup.materials)
    any_nonlinear = any_nonlinear || b.spline_curves || !make_material<3>(b.kind)->tangent_is_constant();
  if (reduction.modal_derivatives && any_nonlinear) {
    t = Clock::now();
    const Eigen::Index k = std::min<Eigen::Index>(reduction.derivative_modes, modes.modes.cols());
    Matrix seeds(setup.num_dofs(), k + (reduction.static_responses ? responses.cols() : 0));
    seeds.leftCols(k) = modes.modes.leftCols(k);
    if (reduction.static_responses) {
      // Scaled like the modes (M-norm 1) so that the derivative's finite-difference step fits.
      for (Eigen::Index c = 0; c < responses.cols(); ++c)
        seeds.col(k + c) = responses.col(c) / std::sqrt(responses.col(c).dot(mass * responses.col(c)));
    }
    if (reduction.krylov_order == 2) {
      blocks.push_back(modal_derivatives(model, x0, p0, seeds));
    } else if (reduction.krylov_order > 2) {  // blocks 2..k of the static-response recurrence
      KrylovRecurrenceOptions krylov;
      krylov.order = reduction.krylov_order;
      const KrylovRecurrence recurrence = krylov_recurrence(model, x0, p0, mass, seeds, krylov);
      for (std::size_t j = 1; j < recurrence.blocks.size(); ++j) blocks.push_back(recurrence.blocks[j]);
    }
    design.timings.modal_derivatives = seconds_since(t);
  }
  Eigen::Index columns = 0;
  for (const Matrix& b : blocks) columns += b.cols();
  Matrix candidates(setup.num_dofs(), columns);
  columns = 0;
  for (const Matrix& b : blocks) {
    candidates.middleCols(columns, b.cols()) = b;
    columns += b.cols();
  }
  design.basis_candidates = static_cast<int>(columns);
  design.basis = mass_orthonormal_basis(candidates, mass, 1e-6);
  if (reduction.basis != "global") design.basis = local_basis(reduction, model, mesh, x0, p0, mass, design.basis,
                                                                setup.nodal_forces, handle_loads);

  design.mass = mass;
  precompute(design);
  design.timings.total = seconds_since(t_begin);
  return design;
}

void set_handle_targets(ReducedDesign& design, const std::vector<Eigen::VectorXd>& targets) {
  const int dim = design.setup.dim();
  if (targets.size() != design.handles.size())
    throw std::invalid_argument("set_handle_targets: " + std::to_string(design.handles.size()) +
                                " handle targets wanted, got " + std::to_string(targets.size()));
  for (std::size_t h = 0; h < targets.size(); ++h) {
    const std::string name = "set_handle_targets: the target of " + design.handles[h].key;
    if (targets[h].size() != dim)
      throw std::invalid_argument(name + " needs " + std::to_string(dim) + " components, not " +
                                  std::to_string(targets[h].size()));
    if (!targets[h].allFinite() || !(targets[h].norm() > 0.0))
      throw std::invalid_argument(name + " must be finite and not zero");
  }
  for (std::size_t h = 0; h < targets.size(); ++h) design.handles[h].target = targets[h];
  Vector target, weights;
  observation_targets(design, target, weights);
  design.functional->set_observations(std::move(target), std::move(weights));
}

FullSpaceCheck full_space_check(const ReducedDesign& design, const Vector& w,
                                const Vector* start_displacement) {
  return full_space_solve(design, design.youngs_modulus(w), start_displacement);
}

FullSpaceCheck full_space_solve(const ReducedDesign& design, const Eigen::VectorXd& youngs_modulus,
                                const Vector* start_displacement) {
  const auto t0 = Clock::now();
  FullSpaceCheck check;
  StaticSetup setup = design.setup;
  setup.youngs_modulus = youngs_modulus;
  check.min_youngs_modulus = setup.youngs_modulus.minCoeff();
  if (!(check.min_youngs_modulus > 0.0)) {
    check.message = "the design has a Young's modulus <= 0 (" + std::to_string(check.min_youngs_modulus) +
                    "): no full-space solve";
    check.seconds = seconds_since(t0);
    return check;
  }
  const StaticSolution solution = start_displacement
                                      ? solve_static_from(setup, setup.rest_state() + *start_displacement)
                                      : solve_static(setup);
  check.converged = solution.converged;
  check.message = solution.message;
  check.displacement = solution.positions - setup.rest_state();
  if (solution.converged) check.handle_errors = design.handle_errors(check.displacement);
  check.seconds = seconds_since(t0);
  return check;
}

ReducedDesignRun run_reduced_design_scene(const Scene& scene, const std::string& out_dir, std::ostream* log,
                                          std::ostream* progress) {
  ReducedDesign design = build_reduced_design(scene);
  return run_reduced_design(design, out_dir, log, progress);
}

ReducedDesignRun run_reduced_design(ReducedDesign& design, const std::string& out_dir, std::ostream* log,
                                    std::ostream* progress) {
  ReducedDesignRun run;
  run.timings = design.timings;
  run.reduced_size = static_cast<int>(design.basis.cols());
  run.material_modes = design.num_design();
  run.coefficient_width = coefficient_width(*design.functional);
  run.basis_candidates = design.basis_candidates;
  if (log)
    *log << "reduced design of " << design.scene_name << ": r = " << run.reduced_size
         << " displacement coordinates (" << run.basis_candidates
         << " candidates), m = " << run.material_modes << " material modes, "
         << design.setup.mesh.num_elements() << " elements; precomputation " << design.timings.total
         << " s\n";
  if (log && design.cubature)
    *log << "cubature: " << design.cubature->elements << " of " << design.cubature->mesh_elements
         << " elements, training error " << design.cubature->training_error << " over "
         << design.cubature->training_poses << " poses, " << design.cubature->seconds << " s\n";
  OptimizerOptions options = design.optimizer;
  options.checkpoint_every = 0;
  options.on_checkpoint = nullptr;
  MillisecondsColumn column(progress ? *progress : std::cout);
  std::ostream with_ms(&column);
  options.progress = progress ? &with_ms : nullptr;
  // Reduced optimization; then, while the full-space handle error exceeds the tolerance, refine
  // the basis at the design reached and continue from it.
  Vector w = Vector::Zero(design.num_design());
  for (int pass = 0;; ++pass) {
    OptimizerResult result = minimize(*design.functional, w, Bounds{}, {}, options);
    with_ms.flush();
    std::vector<double> pass_ms;
    for (std::size_t i = 1; i < result.history.size(); ++i)
      pass_ms.push_back(1e3 * (result.history[i].seconds - result.history[i - 1].seconds));
    run.iteration_ms.insert(run.iteration_ms.end(), pass_ms.begin(), pass_ms.end());
    ReducedDesignPass record;
    record.median_iteration_ms = median(pass_ms);
    record.reduced_size = static_cast<int>(design.basis.cols());
    record.iterations = result.history.empty() ? 0 : result.history.back().iteration;
    record.seconds = result.seconds;
    record.status = to_string(result.status);
    w = result.z;
    run.q.resize(0);
    run.reduced_errors.clear();
    try {
      run.q = design.functional->solve(w);
      run.reduced_errors = design.handle_errors(design.reduced_displacement(run.q));
    } catch (const EvaluationError& e) {
      if (log) *log << "the reduced equilibrium at the best design failed: " << e.what() << "\n";
    }
    if (!run.reduced_errors.empty())
      record.reduced_error = *std::max_element(run.reduced_errors.begin(), run.reduced_errors.end());
    if (pass == 0) {
      run.result = std::move(result);
    } else {
      // One result over the passes: the history goes on, counts and seconds add up.
      const double t_offset = run.result.history.empty() ? 0.0 : run.result.history.back().seconds;
      const int i_offset = run.result.history.empty() ? 0 : run.result.history.back().iteration;
      for (std::size_t i = 1; i < result.history.size(); ++i) {
        OptimizerIteration row = result.history[i];
        row.iteration += i_offset;
        row.seconds += t_offset;
        run.result.history.push_back(row);
      }
      run.result.status = result.status;
      run.result.message = result.message;
      run.result.z = result.z;
      run.result.objective = result.objective;
      run.result.evaluations += result.evaluations;
      run.result.failed_evaluations += result.failed_evaluations;
      run.result.seconds += result.seconds;
      run.result.counters = result.counters;
    }
    if (!design.spec.full_space_check) {
      run.passes.push_back(record);
      break;
    }
    // From the reduced solution when there is one: it is close (that is what is checked).
    const Vector start = run.q.size() > 0 ? design.reduced_displacement(run.q) : Vector();
    run.full = full_space_check(design, w, run.q.size() > 0 ? &start : nullptr);
    if (!run.full->handle_errors.empty())
      record.full_error = *std::max_element(run.full->handle_errors.begin(), run.full->handle_errors.end());
    run.passes.push_back(record);
    if (log)
      *log << "pass " << pass << ": r = " << record.reduced_size << ", " << record.iterations
           << " iterations (median " << record.median_iteration_ms << " ms), reduced handle error "
           << record.reduced_error << ", full-space " << record.full_error << "\n";
    if (!run.full->converged || record.full_error <= design.spec.full_space_tolerance ||
        pass >= design.spec.refinements)
      break;
    const double seconds = refine_basis(design, w, run.full->displacement);
    if (log)
      *log << "refined the basis at the design: r = " << design.basis.cols() << " (" << seconds << " s)\n";
  }
  run.timings = design.timings;
  run.reduced_size = static_cast<int>(design.basis.cols());
  run.coefficient_width = coefficient_width(*design.functional);
  run.basis_candidates = design.basis_candidates;
  run.cubature = design.cubature;
  run.median_iteration_ms = median(run.iteration_ms);

  if (!out_dir.empty() && writes_output()) {  // rank 0 alone in a replicated MPI run
    std::filesystem::create_directories(out_dir);
    run.report_path = (std::filesystem::path(out_dir) / "report.json").string();
    nlohmann::ordered_json report;
    add_report_header(report);
    report["kind"] = "reduced_design";
    report["scene"] = {{"name", design.scene_name}, {"source", design.scene_source}};
    // The full-space check's solver (the reduced loop itself solves its small systems densely).
    report["linear_solver"] = linear_solver_json(design.setup.solver.newton.linear_solver.get());
    report["reduction"] = {{"displacement_modes", design.spec.displacement_modes},
                           {"modal_derivatives", design.spec.modal_derivatives},
                           {"derivative_modes", design.spec.derivative_modes},
                           {"static_responses", design.spec.static_responses},
                           {"design_responses", design.spec.design_responses},
                           {"smoothness", design.spec.smoothness},
                           {"refinements", design.spec.refinements},
                           {"full_space_tolerance", design.spec.full_space_tolerance},
                           {"min_relative_modulus", design.spec.min_relative_modulus},
                           {"positivity_weight", design.spec.positivity_weight},
                           {"krylov_order", design.spec.krylov_order},
                           {"basis", design.spec.basis}};
    report["sizes"] = {
        {"elements", design.setup.mesh.num_elements()}, {"dofs", design.setup.num_dofs()},
        {"reduced_coordinates", run.reduced_size},      {"basis_candidates", run.basis_candidates},
        {"material_modes", run.material_modes},         {"coefficient_width", run.coefficient_width}};
    const ReducedDesignTimings& tm = design.timings;
    report["precomputation_seconds"] = {{"setup", tm.setup},
                                        {"displacement_modes", tm.displacement_modes},
                                        {"responses", tm.responses},
                                        {"modal_derivatives", tm.modal_derivatives},
                                        {"material_modes", tm.material_modes},
                                        {"coefficients", tm.coefficients},
                                        {"cubature", tm.cubature},
                                        {"refinement", tm.refinement},
                                        {"total", tm.total}};
    if (design.cubature) {
      const ReducedDesignCubature& c = *design.cubature;
      report["cubature"] = {{"elements", c.elements},
                            {"mesh_elements", c.mesh_elements},
                            {"training_poses", c.training_poses},
                            {"training_error", c.training_error},
                            {"seconds", c.seconds},
                            {"exact", c.exact}};
    }
    const OptimizerResult& r = run.result;
    nlohmann::ordered_json passes = nlohmann::ordered_json::array();
    for (const ReducedDesignPass& pr : run.passes)
      passes.push_back({{"reduced_coordinates", pr.reduced_size},
                        {"iterations", pr.iterations},
                        {"seconds", pr.seconds},
                        {"median_iteration_ms", pr.median_iteration_ms},
                        {"status", pr.status},
                        {"reduced_error", pr.reduced_error},
                        {"full_error", pr.full_error}});
    report["passes"] = passes;
    report["optimizer"] = {{"backend", to_string(design.optimizer.backend)},
                           {"status", to_string(r.status)},
                           {"message", r.message},
                           {"iterations", r.history.empty() ? 0 : r.history.back().iteration},
                           {"evaluations", r.evaluations},
                           {"failed_evaluations", r.failed_evaluations},
                           {"seconds", r.seconds},
                           {"median_iteration_ms", run.median_iteration_ms},
                           {"objective", r.objective}};
    report["w"] = to_json(r.z);
    const Eigen::VectorXd E = design.youngs_modulus(r.z);
    report["youngs_modulus"] = {{"min", E.minCoeff()}, {"max", E.maxCoeff()}};
    nlohmann::ordered_json handles = nlohmann::ordered_json::array();
    for (std::size_t h = 0; h < design.handles.size(); ++h) {
      nlohmann::ordered_json item = {{"key", design.handles[h].key},
                                     {"target_displacement", to_json(design.handles[h].target)}};
      if (h < run.reduced_errors.size()) item["reduced_error"] = run.reduced_errors[h];
      if (run.full && h < run.full->handle_errors.size()) item["full_error"] = run.full->handle_errors[h];
      handles.push_back(item);
    }
    report["handles"] = handles;
    if (!run.reduced_errors.empty())
      report["max_reduced_error"] = *std::max_element(run.reduced_errors.begin(), run.reduced_errors.end());
    if (run.full) {
      report["full_space"] = {
          {"converged", run.full->converged}, {"message", run.full->message}, {"seconds", run.full->seconds}};
      if (!run.full->handle_errors.empty())
        report["max_full_error"] =
            *std::max_element(run.full->handle_errors.begin(), run.full->handle_errors.end());
    }
    write_report_file(run.report_path, report);
  }
  if (log) {
    *log << run.result.report();
    *log << "median " << run.median_iteration_ms << " ms per iteration\n";
    for (std::size_t h = 0; h < design.handles.size(); ++h) {
      *log << design.handles[h].key << ": reduced error "
           << (h < run.reduced_errors.size() ? std::to_string(run.reduced_errors[h]) : std::string("-"));
      if (run.full)
        *log << ", full-space error "
             << (h < run.full->handle_errors.size() ? std::to_string(run.full->handle_errors[h])
                                                    : "- (" + run.full->message + ")");
      *log << "\n";
    }
    if (!run.report_path.empty()) *log << "wrote " << run.report_path << "\n";
  }
  return run;
}

}  // namespace tailor
