#include "problems/fem/static_scene.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ostream>
#include <random>
#include <stdexcept>
#include <string>

#include "forward/core/format_number.hpp"
#include "forward/core/timing.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/fem/loads.hpp"
#include "forward/fem/materials/spline_material.hpp"
#include "forward/fem/quadratic_elastic_term.hpp"
#include "forward/fem/quadratic_loads.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "forward/reduction/free_space.hpp"
#include "problems/fem/linear_solver_choice.hpp"
#include "problems/fem/scene_selection.hpp"

namespace tailor {
namespace {

Mesh make_mesh(const MeshSpec& spec) {
  switch (spec.kind) {
    case MeshSpec::Kind::file:
      return read_mesh(spec.file);
    case MeshSpec::Kind::box:
      return box_tet_mesh(spec.min, spec.max, spec.cells[0], spec.cells[1], spec.cells[2]);
    case MeshSpec::Kind::rectangle:
      return rectangle_triangle_mesh(spec.min, spec.max, spec.cells[0], spec.cells[1]);
  }
  throw std::logic_error("make_mesh: unknown mesh kind");
}

// Per-element material data; every element covered by exactly one material entry.
void assign_materials(const Scene& scene, StaticSetup& setup) {
  const Mesh& mesh = setup.mesh;
  const int ne = mesh.num_elements();
  setup.element_material = Eigen::VectorXi::Constant(ne, -1);
  setup.youngs_modulus.resize(ne);
  setup.poisson_ratio.resize(ne);
  setup.density.resize(ne);
  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    const MaterialSpec& spec = scene.materials[m];
    if (!spec.youngs_modulus_values.empty() && static_cast<int>(spec.youngs_modulus_values.size()) != ne)
      throw_scene_error(scene, spec.key + ".youngs_modulus_file",
                        "expected one value per mesh element (" + std::to_string(ne) + "), got " +
                            std::to_string(spec.youngs_modulus_values.size()));
    MaterialBlock block{spec.model, select_elements(scene, mesh, spec.elements), spec.spline_curves};
    for (int e : block.elements) {
      if (const int other = setup.element_material[e]; other >= 0)
        throw_scene_error(scene, spec.elements.key,
                          "element " + std::to_string(e) + " is covered by " + scene.materials[other].key +
                              " already (every element needs exactly one material)");
      setup.element_material[e] = static_cast<int>(m);
      setup.youngs_modulus[e] =
          spec.youngs_modulus_values.empty() ? spec.youngs_modulus : spec.youngs_modulus_values[e];
      setup.poisson_ratio[e] = spec.poisson_ratio;
      setup.density[e] = spec.density;
    }
    setup.materials.push_back(std::move(block));
  }
  for (int e = 0; e < ne; ++e)
    if (setup.element_material[e] < 0)
      throw_scene_error(scene, "materials",
                        "element " + std::to_string(e) + " (region " +
                            std::to_string(mesh.element_regions.size() == ne ? mesh.element_regions[e] : 0) +
                            ") is covered by no material (every element needs exactly one)");
}

// The nodes a vertex selection holds: the vertices, and with quadratic elements the node of
// every edge whose two ends are selected (so a clamped face holds its edge nodes too, while a
// list of single vertices holds only those).
std::vector<int> spec_nodes(const StaticSetup& setup, std::vector<int> vertices) {
  if (!setup.quadratic) return vertices;
  const QuadraticMesh& q = *setup.quadratic;
  std::vector<bool> selected(static_cast<std::size_t>(q.num_corners()), false);
  for (int v : vertices) selected[static_cast<std::size_t>(v)] = true;
  for (int i = 0; i < q.edges.rows(); ++i)
    if (selected[static_cast<std::size_t>(q.edges(i, 0))] && selected[static_cast<std::size_t>(q.edges(i, 1))])
      vertices.push_back(q.num_corners() + i);
  return vertices;
}

std::string node_name(const StaticSetup& setup, int node) {
  if (node < setup.mesh.num_vertices()) return "vertex " + std::to_string(node);
  const int edge = node - setup.mesh.num_vertices();
  return "the edge node between vertices " + std::to_string(setup.quadratic->edges(edge, 0)) + " and " +
         std::to_string(setup.quadratic->edges(edge, 1));
}

void assign_dirichlet(const Scene& scene, StaticSetup& setup) {
  const int dim = setup.dim();
  setup.prescribed_displacement = Vector::Zero(setup.num_dofs());
  std::vector<int> owner(static_cast<std::size_t>(setup.num_dofs()), -1);
  for (std::size_t c = 0; c < scene.dirichlet.size(); ++c) {
    const DirichletSpec& spec = scene.dirichlet[c];
    Eigen::VectorXd u = Eigen::VectorXd::Zero(dim);
    if (spec.displacement.size() > 0) {
      check_dimension(scene, setup.mesh, spec.displacement, spec.key + ".displacement");
      u = spec.displacement;
    }
    std::vector<int> components = spec.components;
    if (components.empty())
      for (int k = 0; k < dim; ++k) components.push_back(k);
    for (int k : components)
      if (k >= dim)
        throw_scene_error(
            scene, spec.key + ".components",
            "component " + std::to_string(k) + " does not exist in a " + std::to_string(dim) + "D mesh");
    for (int v : spec_nodes(setup, select_vertices(scene, setup.mesh, spec.vertices)))
      for (int k : components) {
        const int dof = dim * v + k;
        const int previous = owner[static_cast<std::size_t>(dof)];
        if (previous >= 0 && setup.prescribed_displacement[dof] != u[k])
          throw_scene_error(scene, spec.key,
                            "prescribes " + node_name(setup, v) + " component " + std::to_string(k) +
                                " differently from " + scene.dirichlet[previous].key);
        owner[static_cast<std::size_t>(dof)] = static_cast<int>(c);
        setup.prescribed_displacement[dof] = u[k];
      }
  }
  for (int dof = 0; dof < setup.num_dofs(); ++dof)
    if (owner[static_cast<std::size_t>(dof)] >= 0) setup.fixed_dofs.push_back(dof);
}

void assign_loads(const Scene& scene, StaticSetup& setup) {
  const Mesh& mesh = setup.mesh;
  const int dim = setup.dim();
  const LoadSpec& loads = scene.loads;
  setup.has_loads = loads.any();
  setup.nodal_forces = Vector::Zero(setup.num_dofs());
  if (loads.gravity) {
    check_dimension(scene, mesh, *loads.gravity, loads.gravity_key);
    if (setup.density.maxCoeff() <= 0.0)
      throw_scene_error(scene, loads.gravity_key,
                        "has no effect: every material has density 0 (give materials a density)");
    setup.nodal_forces += setup.quadratic ? quadratic_gravity_forces(*setup.quadratic, setup.density, *loads.gravity)
                                          : gravity_forces(mesh, setup.density, *loads.gravity);
  }
  for (const TractionSpec& t : loads.tractions) {
    check_dimension(scene, mesh, t.traction, t.key + ".traction");
    const Eigen::MatrixXi facets = select_boundary_facets(scene, mesh, t.faces);
    setup.nodal_forces += setup.quadratic ? quadratic_traction_forces(*setup.quadratic,
                                                                      quadratic_facets(*setup.quadratic, facets), t.traction)
                                          : traction_forces(mesh, facets, t.traction);
  }
  for (const NodalForceSpec& n : loads.nodal) {
    check_dimension(scene, mesh, n.force, n.key + ".force");
    for (int v : select_vertices(scene, mesh, n.vertices))
      setup.nodal_forces.segment(dim * v, dim) += n.force;
  }
  if (loads.nodal_file) {
    const NodalForceFile& file = *loads.nodal_file;
    if (file.forces.cols() != dim)
      throw_scene_error(scene, file.key,
                        "expected " + std::to_string(dim) + " force components per line (the mesh is " +
                            std::to_string(dim) + "D), got " + std::to_string(file.forces.cols()));
    for (std::size_t r = 0; r < file.vertices.size(); ++r) {
      const int v = file.vertices[r];
      if (v >= mesh.num_vertices())
        throw_scene_error(scene, file.key,
                          "vertex " + std::to_string(v) + " does not exist (the mesh has " +
                              std::to_string(mesh.num_vertices()) + " vertices)");
      setup.nodal_forces.segment(dim * v, dim) += file.forces.row(static_cast<Eigen::Index>(r)).transpose();
    }
  }
}

template <int Dim>
void add_elastic_terms(const StaticSetup& setup, Model& model, int youngs_offset, int poisson_offset) {
  for (const MaterialBlock& block : setup.materials) {
    std::shared_ptr<const Material<Dim>> material =
        block.spline_curves ? std::make_shared<const SplineMaterial<Dim>>(*block.spline_curves)
                            : std::shared_ptr<const Material<Dim>>(make_material<Dim>(block.kind));
    if (setup.quadratic)
      model.add(std::make_unique<QuadraticElasticTerm<Dim>>(*setup.quadratic, material, youngs_offset, poisson_offset,
                                                            block.elements));
    else
      model.add(std::make_unique<ElasticTerm<Dim>>(setup.mesh, material, youngs_offset, poisson_offset,
                                                   block.elements));
  }
}

// Calls f(term) for each term of the model of type Term.
template <class Term, class F>
void for_each_term_of_type(const Model& model, F&& f) {
  for (const auto& term : model.terms())
    if (const auto* elastic = dynamic_cast<const Term*>(term.get())) f(*elastic);
}

template <int Dim>
void postprocess(const StaticSetup& setup, const Model& model, const Vector& p, StaticSolution& out) {
  const Vector& x = out.positions;
  out.stresses = Eigen::MatrixXd::Zero(setup.mesh.num_elements(), Dim * Dim);
  Vector elastic_gradient = Vector::Zero(x.size());
  auto collect = [&](const auto& term) {
    const Eigen::MatrixXd stresses = term.stresses(x, p);
    for (std::size_t k = 0; k < term.elements().size(); ++k)
      out.stresses.row(term.elements()[k]) = stresses.row(static_cast<Eigen::Index>(k));
    term.add_gradient(x, p, elastic_gradient);
  };
  for_each_term_of_type<ElasticTerm<Dim>>(model, collect);
  for_each_term_of_type<QuadraticElasticTerm<Dim>>(model, collect);
  out.reaction_force_total = Eigen::VectorXd::Zero(Dim);
  for (int dof : setup.fixed_dofs) out.reaction_force_total[dof % Dim] -= elastic_gradient[dof];
}

}  // namespace

Vector StaticSetup::rest_state() const {
  if (quadratic) return quadratic_rest_state(*quadratic);
  const Eigen::MatrixXd transposed = mesh.rest_positions.transpose();  // dim x nv, column-major = interleaved
  return Eigen::Map<const Vector>(transposed.data(), transposed.size());
}

Vector StaticSetup::parameters() const {
  Vector p(2 * mesh.num_elements());
  p << youngs_modulus, poisson_ratio;
  return p;
}

StaticSetup setup_static_scene(const Scene& scene) {
  StaticSetup setup;
  setup.mesh = make_mesh(scene.mesh);
  if (scene.mesh.order == 2) setup.quadratic = std::make_shared<const QuadraticMesh>(make_quadratic_mesh(setup.mesh));
  setup.solver = scene.solver;
  assign_materials(scene, setup);
  assign_dirichlet(scene, setup);
  assign_loads(scene, setup);
  return setup;
}

std::vector<std::string> free_rigid_motions(const StaticSetup& setup, const std::vector<int>& fixed_dofs) {
  std::vector<int> vertex_dofs = fixed_dofs;
  std::erase_if(vertex_dofs, [&](int dof) { return dof >= setup.dim() * setup.mesh.num_vertices(); });
  return unconstrained_rigid_motions(setup.mesh, vertex_dofs);
}

void require_linear_elements(const Scene& scene, const std::string& what) {
  if (scene.mesh.order == 1) return;
  throw_scene_error(scene, "mesh.order",
                    "quadratic elements (order 2) are available for static solves (simulate, check) and "
                    "inverse problems with a full-space design; not yet for " + what + ": use \"order\": 1");
}

void require_supported(const Scene& scene, const StaticSetup& setup) {
  const std::vector<std::string> free = free_rigid_motions(setup, setup.fixed_dofs);
  if (free.empty()) return;
  std::string list;
  for (const std::string& motion : free) list += (list.empty() ? "" : "; ") + motion;
  throw_scene_error(scene, "dirichlet",
                    "the supports leave the body free to move rigidly (" + list +
                        "), so it has no static equilibrium: fix at least " +
                        (setup.dim() == 3 ? "3 non-collinear vertices" : "2 distinct vertices") +
                        " in all components (or simulate it with a \"dynamics\" section)");
}

std::unique_ptr<Model> build_static_model(const StaticSetup& setup, double load_factor) {
  auto model = std::make_unique<Model>(setup.num_dofs());
  const int ne = setup.mesh.num_elements();
  const int youngs_offset = model->parameter_layout().add("youngs_modulus", ne);
  const int poisson_offset = model->parameter_layout().add("poisson_ratio", ne);
  if (setup.dim() == 3)
    add_elastic_terms<3>(setup, *model, youngs_offset, poisson_offset);
  else
    add_elastic_terms<2>(setup, *model, youngs_offset, poisson_offset);
  if (setup.has_loads)
    model->add(std::make_unique<ExternalForceTerm>(load_factor * setup.nodal_forces, "external_force"));
  for (const EnergyTermFactory& make : setup.extra_terms) {
    std::unique_ptr<EnergyTerm> term = make(setup);
    if (!term)
      throw std::invalid_argument("build_static_model: an extra energy term's factory returned null");
    model->add(std::move(term));
  }
  model->set_elimination(Elimination::dirichlet(
      setup.fixed_dofs, setup.rest_state() + load_factor * setup.prescribed_displacement));
  return model;
}

namespace {

// Load steps from rest, or (start set) one step at full load from *start.
StaticSolution solve_static_steps(const StaticSetup& setup, const Vector* start, std::ostream* progress) {
  StaticSolution out;
  const Vector p = setup.parameters();
  const int num_steps = start ? 1 : setup.solver.load_steps;
  NewtonOptions options = setup.solver.newton;
  if (progress) options.progress = progress;  // else the setup's own (none unless a caller set one)
  progress = options.progress;
  std::unique_ptr<Model> model;
  Vector y;
  for (int step = 1; step <= num_steps; ++step) {
    const double factor = static_cast<double>(step) / num_steps;
    auto t0 = Clock::now();
    // Dead loads cannot be rescaled in place, so each step gets its own model (cheap next to
    // the solve); the free unknowns keep their order, so y warm-starts the next step.
    model = build_static_model(setup, factor);
    out.model_seconds += seconds_since(t0);
    if (step == 1) y = model->elimination().restrict_state(start ? *start : setup.rest_state());
    if (progress && num_steps > 1)
      *progress << "load step " << step << "/" << num_steps << " (factor " << factor << ")\n";
    if (options.linear_solver)  // the rigid-body modes for algebraic multigrid, when whole vertices are free
      give_vertex_coordinates(*options.linear_solver, model->elimination(), setup.dim(), setup.rest_state());
    NewtonSolver solver(*model, options);
    LoadStep load_step{factor, solver.solve(p, y)};
    const NewtonResult& r = load_step.newton;
    out.analysis_seconds += r.analysis_seconds;
    for (const NewtonIteration& it : r.history) {
      out.assembly_seconds += it.assembly_seconds;
      out.factorization_seconds += it.factorization_seconds;
      out.solve_seconds += it.solve_seconds;
      out.line_search_seconds += it.line_search_seconds;
    }
    out.converged = r.converged();
    out.status = to_string(r.status);
    out.message = num_steps > 1 ? "load step " + std::to_string(step) + "/" + std::to_string(num_steps) +
                                      ": " + r.message
                                : r.message;
    out.steps.push_back(std::move(load_step));
    if (!out.converged) break;
  }

  out.num_free = model->elimination().num_free();
  out.positions = model->elimination().expand(y);
  out.energy = model->energy(out.positions, p);
  // The residual at the result, evaluated afresh (not Newton's own record): a solve reported as
  // converged must agree with it, else it is reported as failed (a model that is not the same
  // function in the solve and at the end, as a rod's twisting moment once was, would otherwise
  // report a wrong "converged").
  out.residual = model->elimination().reduce(model->gradient(out.positions, p)).norm();
  if (out.converged && !out.steps.empty()) {
    const NewtonResult& last = out.steps.back().newton;
    const double allowed = 10.0 * std::max({last.final_residual, last.residual_floor, 1e-300});
    if (!(out.residual <= allowed)) {
      out.converged = false;
      out.status = "inconsistent_residual";
      out.message = "the solver reported convergence with residual " + format_number(last.final_residual) +
                    ", but the residual at the result is " + format_number(out.residual);
    }
  }
  const Vector u = out.positions - setup.rest_state();
  out.displacement =  // the corners' (the head of the state) with quadratic elements
      Eigen::Map<const Eigen::MatrixXd>(u.data(), setup.dim(), setup.mesh.num_vertices()).transpose();
  const Eigen::VectorXd norms = out.displacement.rowwise().norm();
  out.max_displacement = norms.size() ? norms.maxCoeff(&out.max_displacement_vertex) : 0.0;
  if (setup.dim() == 3)
    postprocess<3>(setup, *model, p, out);
  else
    postprocess<2>(setup, *model, p, out);
  return out;
}

}  // namespace

StaticSolution solve_static(const StaticSetup& setup, std::ostream* progress) {
  return solve_static_steps(setup, nullptr, progress);
}

StaticSolution solve_static_from(const StaticSetup& setup, const Vector& start, std::ostream* progress) {
  if (start.size() != setup.num_dofs())
    throw std::invalid_argument("solve_static_from: the start state has " + std::to_string(start.size()) +
                                " entries, the mesh " + std::to_string(setup.num_dofs()) + " DOFs");
  StaticSolution warm = solve_static_steps(setup, &start, progress);
  if (warm.converged) return warm;
  return solve_static_steps(setup, nullptr, progress);
}

std::vector<EnergyTermCheck> check_static_scene(const StaticSetup& setup, unsigned seed) {
  const std::unique_ptr<Model> model = build_static_model(setup, 1.0);
  const Vector p = setup.parameters();
  // Perturb the prescribed state by a fraction of the element size, small enough that no
  // element inverts (the energies of nonlinear materials are singular there).
  const double mean_measure = element_volumes(setup.mesh).mean();
  const double element_size = std::pow(mean_measure, 1.0 / setup.dim());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Vector x = setup.rest_state() + setup.prescribed_displacement;
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += 0.02 * element_size * uniform(rng);

  DerivativeCheckOptions options;
  options.seed = seed;
  options.state_scale = element_size;
  options.hessian_mode = HessianMode::exact;
  std::vector<EnergyTermCheck> checks;
  for (const auto& term : model->terms()) checks.push_back(check_energy_term(*term, x, p, options));
  return checks;
}

bool check_failed(const EnergyTermCheck& check) {
  for (const DerivativeCheck& c : check.checks)
    if (!c.passed && !c.vanishing) return true;
  return false;
}

}  // namespace tailor
