#include "problems/fem/inverse_handles.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <limits>
#include <map>

#include "forward/fem/elastic_term.hpp"
#include "forward/fem/loads.hpp"
#include "forward/fem/quadratic_elastic_term.hpp"
#include "forward/reduction/free_space.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/fem/scene_selection.hpp"

namespace tailor {

HandlesTerm parse_handles_term(const SceneNode& node, const std::string& directory) {
  HandlesTerm term;
  if (auto a = node.find("alpha")) term.alpha = a->non_negative();
  if (auto b = node.find("beta")) term.beta = b->non_negative();
  const SceneNode list = node.at("handles");
  for (const SceneNode& item : list.items()) {
    item.expect_keys({"vertices", "displacement", "force", "force_per_vertex", "weight"});
    HandleSpec h;
    h.key = item.path();
    h.vertices = parse_vertex_selector(item.at("vertices"), directory);
    if (auto d = item.find("displacement")) h.displacement = d->vector();
    if (item.has("force") && item.has("force_per_vertex"))
      item.at("force_per_vertex")
          .fail("give either \"force\" (total over the handle) or \"force_per_vertex\", not both");
    if (auto f = item.find("force")) h.force = f->vector();
    if (auto f = item.find("force_per_vertex")) {
      h.force = f->vector();
      h.force_per_vertex = true;
    }
    if (!h.displacement && !h.force)
      item.fail("a handle needs a target: \"displacement\", \"force\" or \"force_per_vertex\" (or several)");
    if (auto w = item.find("weight")) h.weight = w->non_negative();
    term.handles.push_back(std::move(h));
  }
  if (term.handles.empty()) list.fail("expected at least one handle");
  return term;
}

ParameterBlock HandleDesign::parameter_block() const {
  return {offset, scale_map(Vector::Constant(size(), scale))};
}

void HandleDesign::prescribe(const Vector& z_u, StaticSetup& setup) const {
  for (int k = 0; k < size(); ++k)
    setup.prescribed_displacement[objective->dofs()[static_cast<std::size_t>(k)]] = scale * z_u[k];
}

const HandlesTerm* find_handles_term(const InverseSpec& spec, std::string* key) {
  for (const ObjectiveTermSpec& t : spec.objective)
    if (const auto* handles = t.settings_as<HandlesTerm>()) {
      if (key) *key = t.key;
      return handles;
    }
  return nullptr;
}

std::vector<std::vector<int>> constrain_handles(const Scene& scene, InverseProblem& problem,
                                                const HandlesTerm& term, const std::string& key) {
  StaticSetup& setup = problem.setup;
  const Mesh& mesh = setup.mesh;
  const int dim = mesh.dim();
  std::vector<bool> fixed(static_cast<std::size_t>(setup.num_dofs()), false);
  for (int d : setup.fixed_dofs) fixed[static_cast<std::size_t>(d)] = true;
  std::map<int, std::string> owner;  // vertex -> the handle holding it
  std::vector<std::vector<int>> vertices;
  for (const HandleSpec& h : term.handles) {
    if (h.displacement) check_dimension(scene, mesh, *h.displacement, h.key + ".displacement");
    if (h.force)
      check_dimension(scene, mesh, *h.force, h.key + (h.force_per_vertex ? ".force_per_vertex" : ".force"));
    vertices.push_back(select_vertices(scene, mesh, h.vertices));
    for (int v : vertices.back()) {
      if (const auto [it, fresh] = owner.emplace(v, h.key); !fresh)
        throw_scene_error(scene, h.key + ".vertices",
                          "vertex " + std::to_string(v) + " is already in the handle " + it->second +
                              "; a vertex belongs to at most one handle");
      for (int k = 0; k < dim; ++k)
        if (fixed[static_cast<std::size_t>(dim * v + k)])
          throw_scene_error(
              scene, h.key + ".vertices",
              "vertex " + std::to_string(v) +
                  " is also held by a dirichlet condition; handles move their vertices, so they "
                  "must not overlap the supports");
    }
  }
  for (const auto& list : vertices)
    for (int v : list)
      for (int k = 0; k < dim; ++k) setup.fixed_dofs.push_back(dim * v + k);
  std::sort(setup.fixed_dofs.begin(), setup.fixed_dofs.end());

  if (const int free = static_cast<int>(free_rigid_motions(setup, setup.fixed_dofs).size()); free > 0)
    throw_scene_error(scene, key,
                      "the dirichlet conditions and the handles leave the body free to move rigidly (" +
                          std::to_string(free) + " independent rigid motion" + (free == 1 ? "" : "s") +
                          (free == 1 ? " leaves" : " leave") +
                          " every supported and handle vertex in place), so its stiffness matrix is "
                          "singular: hold at least " +
                          (dim == 3 ? "3 non-collinear vertices" : "2 distinct vertices") +
                          " in all components, with dirichlet conditions or handles");
  return vertices;
}

namespace {

// Copies of the scene's elastic terms over the elements touching a handle vertex, and the
// loads on handle vertices: their gradient at the handle DOFs is the full model's.
template <int Dim>
std::vector<std::shared_ptr<const EnergyTerm>> reaction_terms(const InverseProblem& problem,
                                                              const std::vector<bool>& on_handle) {
  const StaticSetup& setup = problem.setup;
  const Mesh& mesh = setup.mesh;
  const int poisson_offset = problem.model->parameter_layout().at("poisson_ratio").offset;
  std::vector<std::shared_ptr<const EnergyTerm>> terms;
  for (const MaterialBlock& block : setup.materials) {
    std::vector<int> touching;
    for (int e : block.elements)
      for (int a = 0; a <= Dim; ++a)
        if (on_handle[static_cast<std::size_t>(mesh.elements(e, a))]) {
          touching.push_back(e);
          break;
        }
    if (touching.empty()) continue;
    if (setup.quadratic)
      terms.push_back(std::make_shared<QuadraticElasticTerm<Dim>>(
          *setup.quadratic, make_material<Dim>(block.kind), problem.youngs_offset, poisson_offset, std::move(touching)));
    else
      terms.push_back(std::make_shared<ElasticTerm<Dim>>(
          mesh, make_material<Dim>(block.kind), problem.youngs_offset, poisson_offset, std::move(touching)));
  }
  if (setup.has_loads) {
    Vector loads = Vector::Zero(setup.num_dofs());
    for (int v = 0; v < mesh.num_vertices(); ++v)  // handle DOFs are vertices' (corners come first)
      if (on_handle[static_cast<std::size_t>(v)])
        loads.segment(Dim * v, Dim) = setup.nodal_forces.segment(Dim * v, Dim);
    terms.push_back(std::make_shared<ExternalForceTerm>(std::move(loads), "external_force"));
  }
  return terms;
}

// u~0 (see attach_handles), in u~ order.
Vector initial_handle_displacements(const InverseProblem& problem, const HandlesTerm& term,
                                    const std::vector<std::vector<int>>& vertices) {
  const int dim = problem.setup.dim();
  StaticSetup free_setup = problem.setup;
  std::vector<bool> released(static_cast<std::size_t>(free_setup.num_dofs()), false);
  bool any_released = false;
  for (std::size_t h = 0; h < term.handles.size(); ++h) {
    const HandleSpec& spec = term.handles[h];
    const double share = spec.force_per_vertex ? 1.0 : 1.0 / static_cast<double>(vertices[h].size());
    for (int v : vertices[h]) {
      if (spec.displacement) {
        free_setup.prescribed_displacement.segment(dim * v, dim) = *spec.displacement;
      } else {
        any_released = true;
        free_setup.has_loads = true;
        free_setup.nodal_forces.segment(dim * v, dim) += share * *spec.force;
        for (int k = 0; k < dim; ++k) released[static_cast<std::size_t>(dim * v + k)] = true;
      }
    }
  }
  Eigen::MatrixXd displacement = Eigen::MatrixXd::Zero(problem.setup.mesh.num_vertices(), dim);
  if (any_released) {
    std::erase_if(free_setup.fixed_dofs, [&](int d) { return released[static_cast<std::size_t>(d)]; });
    if (free_rigid_motions(free_setup, free_setup.fixed_dofs).empty()) {
      const StaticSolution solution = solve_static(free_setup);
      if (solution.converged) displacement = solution.displacement;
    }
  }
  std::vector<double> u;
  for (std::size_t h = 0; h < term.handles.size(); ++h)
    for (int v : vertices[h])
      for (int k = 0; k < dim; ++k)
        u.push_back(term.handles[h].displacement ? (*term.handles[h].displacement)[k] : displacement(v, k));
  return Eigen::Map<const Vector>(u.data(), static_cast<Eigen::Index>(u.size()));
}

}  // namespace

void attach_handles(InverseProblem& problem, const HandlesTerm& term,
                    const std::vector<std::vector<int>>& vertices) {
  const StaticSetup& setup = problem.setup;
  const int dim = setup.dim();
  std::vector<Handle> handles;
  std::vector<int> dofs;
  std::vector<bool> on_handle(static_cast<std::size_t>(setup.mesh.num_vertices()), false);
  for (std::size_t h = 0; h < term.handles.size(); ++h) {
    const HandleSpec& spec = term.handles[h];
    Handle handle;
    handle.vertices = vertices[h];
    handle.weight = spec.weight;
    if (spec.displacement) handle.target_displacement = spec.displacement->transpose();
    if (spec.force)
      handle.target_force =
          spec.force_per_vertex
              ? Vector(spec.force->replicate(static_cast<Eigen::Index>(vertices[h].size()), 1))
              : *spec.force;
    for (int v : vertices[h]) {
      on_handle[static_cast<std::size_t>(v)] = true;
      for (int k = 0; k < dim; ++k) dofs.push_back(dim * v + k);
    }
    handles.push_back(std::move(handle));
  }
  auto design = std::make_shared<HandleDesign>();
  design->offset = problem.model->add_prescribed_displacements("handle_displacement", dofs);
  auto terms = dim == 3 ? reaction_terms<3>(problem, on_handle) : reaction_terms<2>(problem, on_handle);
  design->objective =
      std::make_shared<HandleObjective>(std::move(terms), setup.num_dofs(), dim, std::move(handles),
                                        design->offset, HandleObjectiveOptions{term.alpha, term.beta});

  const Vector u0 = initial_handle_displacements(problem, term, vertices);
  // The characteristic displacement: the largest target, else the largest initial one, else
  // 1e-3 of the bounding-box diagonal.
  double scale = 0.0;
  for (const HandleSpec& h : term.handles)
    if (h.displacement) scale = std::max(scale, h.displacement->norm());
  for (Eigen::Index i = 0; scale == 0.0 && i + dim <= u0.size(); i += dim)
    scale = std::max(scale, u0.segment(i, dim).norm());
  if (!(scale > 0.0)) {
    const Mesh& mesh = setup.mesh;
    scale =
        1e-3 * (mesh.rest_positions.colwise().maxCoeff() - mesh.rest_positions.colwise().minCoeff()).norm();
  }
  design->scale = scale;
  problem.handles = design;
  const Eigen::Index n = problem.z0.size(), m = u0.size();
  problem.z0.conservativeResize(n + m);
  problem.z0.tail(m) = u0 / scale;
  if (problem.bounds.lower.size() > 0 || problem.bounds.upper.size() > 0) {
    const double inf = std::numeric_limits<double>::infinity();
    problem.bounds.lower.conservativeResize(n + m);
    problem.bounds.lower.tail(m).setConstant(-inf);
    problem.bounds.upper.conservativeResize(n + m);
    problem.bounds.upper.tail(m).setConstant(inf);
  }
}

}  // namespace tailor

namespace tailor {

std::vector<HandleResult> handle_results(const InverseProblem& problem, const Vector& z,
                                         const Vector& positions) {
  std::vector<HandleResult> out;
  const HandlesTerm* term = find_handles_term(problem.spec);
  if (!problem.handles || !term) return out;
  const HandleObjective& handles = *problem.handles->objective;
  const Vector p = problem.parameterization->apply(z);
  const int dim = problem.setup.dim();
  for (int h = 0; h < handles.num_handles(); ++h) {
    const HandleSpec& spec = term->handles[static_cast<std::size_t>(h)];
    const Handle& handle = handles.handle(h);
    HandleResult r;
    r.key = spec.key;
    r.vertices = static_cast<int>(handle.vertices.size());
    r.weight = handle.weight;
    r.total_force = handles.total_force(h, positions, p);
    r.force_per_vertex = spec.force_per_vertex;
    if (spec.force) {
      r.target_force = *spec.force;
      const Vector f = handles.force(h, positions, p), fbar = handle.target_force;
      for (Eigen::Index i = 0; i < f.size(); i += dim)
        r.force_error = std::max(r.force_error, (f.segment(i, dim) - fbar.segment(i, dim)).norm());
      r.relative_force_error = r.force_error / spec.force->norm();
    }
    const Matrix u = handles.displacement(h, p);
    r.displacement = u.colwise().mean().transpose();
    if (spec.displacement) {
      r.target_displacement = *spec.displacement;
      r.displacement_error = (u.rowwise() - spec.displacement->transpose()).rowwise().norm().maxCoeff();
      r.relative_displacement_error = r.displacement_error / spec.displacement->norm();
    }
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace tailor
