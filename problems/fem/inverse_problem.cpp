#include "problems/fem/inverse_problem.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "forward/core/format_number.hpp"
#include "objectives/weighted_sum.hpp"
#include "problems/fem/inverse_handles.hpp"
#include "problems/fem/linear_solver_choice.hpp"
#include "problems/fem/scene_selection.hpp"

namespace tailor {
namespace {

// value * (1 + gradient . c) * inclusion factors, at the element centroids c.
Eigen::VectorXd expression_field(const Scene& scene, const Mesh& mesh, const ModulusField& field) {
  if (field.gradient.size() > 0) check_dimension(scene, mesh, field.gradient, field.key + ".gradient");
  for (std::size_t i = 0; i < field.inclusions.size(); ++i)
    check_dimension(scene, mesh, field.inclusions[i].center,
                    field.key + ".inclusions[" + std::to_string(i) + "].center");
  const int ne = mesh.num_elements();
  Eigen::VectorXd out(ne);
  for (int e = 0; e < ne; ++e) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(mesh.dim());
    for (Eigen::Index k = 0; k < mesh.elements.cols(); ++k)
      c += mesh.rest_positions.row(mesh.elements(e, k)).transpose();
    c /= static_cast<double>(mesh.elements.cols());
    double E = field.value * (field.gradient.size() > 0 ? 1.0 + field.gradient.dot(c) : 1.0);
    for (const ModulusInclusion& inclusion : field.inclusions)
      if ((c - inclusion.center).norm() <= inclusion.radius) E *= inclusion.factor;
    if (!(E > 0.0))
      throw_scene_error(
          scene, field.key,
          "the field is " + format_number(E) + " (not > 0) at the centroid of element " + std::to_string(e));
    out[e] = E;
  }
  return out;
}

}  // namespace

Eigen::VectorXd modulus_field_values(const Scene& scene, const StaticSetup& setup, const ModulusField& field) {
  const int ne = setup.mesh.num_elements();
  if (!field.per_material.empty()) {
    if (field.per_material.size() != scene.materials.size())
      throw_scene_error(scene, field.key + ".materials",
                        "expected one value per materials[] entry (" +
                            std::to_string(scene.materials.size()) + "), got " +
                            std::to_string(field.per_material.size()));
    Eigen::VectorXd out(ne);
    for (int e = 0; e < ne; ++e) out[e] = field.per_material[setup.element_material[e]];
    return out;
  }
  if (field.gradient.size() > 0 || !field.inclusions.empty())
    return expression_field(scene, setup.mesh, field);
  if (field.values.empty()) return Eigen::VectorXd::Constant(ne, field.value);
  if (static_cast<int>(field.values.size()) != ne)
    throw_scene_error(scene, field.key + ".file",
                      "expected one value per mesh element (" + std::to_string(ne) + "), got " +
                          std::to_string(field.values.size()));
  return Eigen::Map<const Eigen::VectorXd>(field.values.data(), ne);
}

void set_truth(const Scene& scene, InverseProblem& problem, const Eigen::VectorXd& truth,
               const std::string& key) {
  if (problem.truth.size() == 0) {
    problem.truth = truth;
    problem.truth_key = key;
  } else if ((problem.truth - truth).cwiseAbs().maxCoeff() > 1e-12 * problem.truth.cwiseAbs().maxCoeff()) {
    throw_scene_error(scene, key, "differs from the true Young's modulus given by " + problem.truth_key);
  }
}

namespace {

// Which design variable each element belongs to, and the variables' names.
void assign_design_groups(const Scene& scene, InverseProblem& problem) {
  const Mesh& mesh = problem.setup.mesh;
  const int ne = mesh.num_elements();
  problem.design_of_element.resize(ne);
  switch (problem.spec.design.granularity) {
    case DesignGranularity::per_element:
      for (int e = 0; e < ne; ++e) {
        problem.design_of_element[e] = e;
        problem.design_labels.push_back("element " + std::to_string(e));
      }
      break;
    case DesignGranularity::per_region: {
      std::map<int, int> index;  // region id -> design variable, in increasing region order
      for (int e = 0; e < ne; ++e)
        index.emplace(mesh.element_regions.size() == ne ? mesh.element_regions[e] : 0, 0);
      for (auto& [region, k] : index) {
        k = static_cast<int>(problem.design_labels.size());
        problem.design_labels.push_back("region " + std::to_string(region));
      }
      for (int e = 0; e < ne; ++e)
        problem.design_of_element[e] =
            index.at(mesh.element_regions.size() == ne ? mesh.element_regions[e] : 0);
      break;
    }
    case DesignGranularity::per_material:
      problem.design_of_element = problem.setup.element_material;
      for (const MaterialSpec& m : scene.materials) problem.design_labels.push_back(m.key);
      break;
    case DesignGranularity::modes:  // modal_initial_design
      break;
  }
}

double to_design(DesignMap map, double value) { return map == DesignMap::log ? std::log(value) : value; }

// z0 (the given initial value, or per design variable the mean of z over its elements: the log
// of the geometric mean of E for the log map) and the bounds in z-space.
void initial_design(const Scene& scene, InverseProblem& problem) {
  const DesignSpec& design = problem.spec.design;
  const int n = static_cast<int>(problem.design_labels.size());
  Vector sum = Vector::Zero(n), count = Vector::Zero(n);
  for (int e = 0; e < problem.setup.mesh.num_elements(); ++e) {
    const double value = design.initial ? *design.initial : problem.setup.youngs_modulus[e];
    sum[problem.design_of_element[e]] += to_design(design.map, value);
    count[problem.design_of_element[e]] += 1.0;
  }
  problem.z0 = sum.cwiseQuotient(count.cwiseMax(1.0));
  const double inf = std::numeric_limits<double>::infinity();
  if (design.min || design.max) {
    problem.bounds.lower = Vector::Constant(n, design.min ? to_design(design.map, *design.min) : -inf);
    problem.bounds.upper = Vector::Constant(n, design.max ? to_design(design.map, *design.max) : inf);
  }
  const Eigen::VectorXd values = problem.design_values(problem.z0);
  for (int k = 0; k < n; ++k)
    if ((design.min && values[k] < *design.min) || (design.max && values[k] > *design.max))
      throw_scene_error(
          scene, "inverse.design",
          "the initial Young's modulus " + format_number(values[k]) + " of " + problem.design_labels[k] +
              " (from the scene's materials) lies outside the bounds [" +
              (design.min ? format_number(*design.min) : "-inf") + ", " +
              (design.max ? format_number(*design.max) : "inf") + "]; give \"initial\" or widen the bounds");
}

// Granularity modes: Phi, y0, z0 and the map z -> E (inverse_modes.hpp), starting at the
// materials' moduli (or "initial" everywhere).
void modal_initial_design(const Scene& scene, InverseProblem& problem) {
  const DesignSpec& design = problem.spec.design;
  const int ne = problem.setup.mesh.num_elements();
  const Eigen::VectorXd initial =
      design.initial ? Eigen::VectorXd::Constant(ne, *design.initial) : problem.setup.youngs_modulus;
  ModalDesignOptions options{design.modes, design.mode_weighting, design.map == DesignMap::log, design.min,
                             design.max};
  const bool too_many = design.modes && *design.modes >= ne;  // material_modes needs r < ne
  try {
    problem.modal = modal_design(problem.setup.mesh, initial, options);
  } catch (const std::invalid_argument& e) {
    if (too_many)
      throw_scene_error(scene, "inverse.design.modes",
                        std::string(e.what()) + " (use \"full\" for one variable per element)");
    throw_scene_error(scene, "inverse.design", e.what());
  } catch (const std::runtime_error& e) {
    throw_scene_error(scene, "inverse.design.modes", e.what());
  }
  problem.z0 = problem.modal->z0;
  for (Eigen::Index j = 0; j < problem.z0.size(); ++j)
    problem.design_labels.push_back((design.modes ? "mode " : "element ") + std::to_string(j));
}

ParameterizationPtr design_map(const InverseProblem& problem) {
  const int n = problem.num_material_design();
  const int ne = problem.setup.mesh.num_elements();
  ParameterizationPtr per_element;
  if (problem.element_map) {
    per_element = problem.element_map;
  } else if (problem.modal) {
    per_element = problem.modal->element_map;
  } else {
    ParameterizationPtr values = problem.spec.design.map == DesignMap::log ? exp_map(n) : identity_map(n);
    per_element = values;
    if (problem.spec.design.granularity != DesignGranularity::per_element) {
      std::vector<int> group(problem.design_of_element.data(), problem.design_of_element.data() + ne);
      per_element = compose(region_scatter_map(std::move(group), n), values);
    }
  }
  std::vector<ParameterBlock> blocks{{problem.youngs_offset, per_element}};
  Vector base = problem.setup.parameters();
  if (problem.handles) {  // u~ / scale after the material design
    base.conservativeResize(problem.model->parameter_layout().size());
    base.segment(problem.handles->offset, problem.handles->size()).setZero();
    blocks.push_back(problem.handles->parameter_block());
  }
  return embed_blocks(std::move(base), std::move(blocks));
}

// The term's objective from its type's build, with the coefficient weight / scale.
ObjectiveTermInfo build_term(const Scene& scene, InverseProblem& problem, const ObjectiveTermSpec& spec) {
  const ObjectiveTermContext context(scene, problem, SceneNode(spec.value, scene.source, spec.key),
                                     spec.settings.get());
  const BuiltObjectiveTerm built = spec.kind->build(context);
  if (!built.objective)
    throw_scene_error(scene, spec.key, "the \"" + spec.type() + "\" term's build returned no objective");
  if (!(built.scale > 0.0) || !std::isfinite(built.scale))
    throw_scene_error(scene, spec.key,
                      "the \"" + spec.type() + "\" term's build returned the scale " +
                          format_number(built.scale) + " (expected a finite number > 0)");
  return {spec.key, spec.type(), spec.weight, spec.weight / built.scale, built.objective};
}

// The reduced functional. Its first Newton solve starts from rest, unless the scene ramps its
// loads: then from the ramped equilibrium at the initial design (later solves warm-start from
// the last one).
std::unique_ptr<StaticFunctional> make_functional(const InverseProblem& problem, ObjectivePtr objective) {
  const Elimination& elimination = problem.model->elimination();
  const Vector rest = elimination.restrict_state(problem.setup.rest_state());
  Vector start = rest;
  if (problem.setup.solver.load_steps > 1) {
    const StaticSolution ramped = solve_static(problem.setup_at(problem.z0));
    if (ramped.converged) start = elimination.restrict_state(ramped.positions);
  }
  StaticFunctionalOptions options;  // keeps its tighter tolerance: gradients need it
  const NewtonOptions& scene_newton = problem.setup.solver.newton;
  options.newton.max_iterations = scene_newton.max_iterations;
  options.newton.hessian = scene_newton.hessian;
  options.newton.reuse_factorization = scene_newton.reuse_factorization;
  options.newton.linear_solver = scene_newton.linear_solver;
  if (options.newton.linear_solver)
    give_vertex_coordinates(*options.newton.linear_solver, elimination, problem.setup.dim(),
                            problem.setup.rest_state());
  options.newton.relative_tolerance =
      std::min(options.newton.relative_tolerance, scene_newton.relative_tolerance);
  // StaticFunctional measures warm starts against the residual at its start state; with load
  // steps that start is already an equilibrium of the initial design, so the absolute floor
  // asks every solve for what a solve from rest at the initial design has to reach.
  const double rest_residual =
      elimination.reduce(problem.model->gradient(elimination.expand(rest), problem.setup.parameters()))
          .norm();
  options.newton.absolute_tolerance =
      std::max(scene_newton.absolute_tolerance, options.newton.relative_tolerance * rest_residual);
  return std::make_unique<StaticFunctional>(*problem.model, problem.parameterization, std::move(objective),
                                            start, options);
}

// A program's own design map (InverseExtensions::element_map), checked against the mesh.
void element_map_design(const InverseExtensions& extensions, InverseProblem& problem) {
  const ParameterizationPtr& map = extensions.element_map;
  const int ne = problem.setup.mesh.num_elements();
  const auto fail = [](const std::string& what) { throw std::invalid_argument("the design map " + what); };
  if (map->num_params() != ne)
    fail("'" + map->name() + "' gives " + std::to_string(map->num_params()) + " values; the mesh has " +
         std::to_string(ne) + " elements (one E each)");
  if (extensions.z0.size() != map->num_design())
    fail("'" + map->name() + "' takes " + std::to_string(map->num_design()) + " design variables; z0 has " +
         std::to_string(extensions.z0.size()));
  for (const Vector* b : {&extensions.bounds.lower, &extensions.bounds.upper})
    if (b->size() != 0 && b->size() != map->num_design())
      fail("bounds need one entry per design variable (" + std::to_string(map->num_design()) + "), got " +
           std::to_string(b->size()));
  const Vector E = map->apply(extensions.z0);
  for (int e = 0; e < ne; ++e)
    if (!(E[e] > 0.0))
      fail("'" + map->name() + "' gives E = " + format_number(E[e]) + " (not > 0) at z0 for element " +
           std::to_string(e));
  problem.element_map = map;
  problem.z0 = extensions.z0;
  problem.bounds = extensions.bounds;
  for (int k = 0; k < map->num_design(); ++k) problem.design_labels.push_back("z[" + std::to_string(k) + "]");
}

}  // namespace

std::unique_ptr<StaticFunctional> make_static_functional(const InverseProblem& problem,
                                                         ObjectivePtr objective) {
  if (!objective) throw std::invalid_argument("make_static_functional: no objective");
  return make_functional(problem, std::move(objective));
}

Eigen::VectorXd InverseProblem::design_values(const Vector& z) const {
  if (element_map) return z.head(num_material_design());
  if (modal) return youngs_modulus(z);
  const Vector material = z.head(num_material_design());
  return spec.design.map == DesignMap::log ? Eigen::VectorXd(material.array().exp())
                                           : Eigen::VectorXd(material);
}

Eigen::VectorXd InverseProblem::youngs_modulus(const Vector& z) const {
  if (element_map) return element_map->apply(Vector(z.head(num_material_design())));
  if (modal) return modal->element_map->apply(Vector(z.head(num_material_design())));
  const Eigen::VectorXd values = design_values(z);
  Eigen::VectorXd out(design_of_element.size());
  for (Eigen::Index e = 0; e < out.size(); ++e) out[e] = values[design_of_element[e]];
  return out;
}

StaticSetup InverseProblem::setup_at(const Vector& z) const {
  StaticSetup out = setup;
  out.youngs_modulus = youngs_modulus(z);
  if (handles) handles->prescribe(z.tail(handles->size()), out);
  return out;
}

std::unique_ptr<InverseProblem> build_inverse_problem(const Scene& scene,
                                                      const InverseExtensions& extensions) {
  if (!scene.inverse)
    throw SceneError(
        scene.source +
        ": (top level): the scene has no \"inverse\" section (tailor run and tailor gradcheck need "
        "one; see docs/scenes.md)");
  const auto t0 = std::chrono::steady_clock::now();
  auto problem = std::make_unique<InverseProblem>();
  problem->scene_name = scene.name;
  problem->scene_source = scene.source;
  problem->spec = *scene.inverse;
  problem->setup = setup_static_scene(scene);
  for (const EnergyTermFactory& make : extensions.energy_terms) problem->setup.extra_terms.push_back(make);
  // Spline materials keep their curves (their elements' Young's modulus is not used), so at
  // least one material must take E from the design.
  bool designable = false;
  for (const MaterialBlock& block : problem->setup.materials) designable = designable || !block.spline_curves;
  if (!designable)
    throw_scene_error(scene, "inverse.design",
                      "every material is a spline material, whose stiffness is its curves: there is no "
                      "Young's modulus to design");

  if (problem->spec.ground_truth)
    set_truth(scene, *problem, modulus_field_values(scene, problem->setup, *problem->spec.ground_truth),
              problem->spec.ground_truth->key);
  if (extensions.element_map) {
    element_map_design(extensions, *problem);
  } else if (problem->spec.design.granularity == DesignGranularity::modes) {
    modal_initial_design(scene, *problem);
  } else {
    assign_design_groups(scene, *problem);
    initial_design(scene, *problem);
  }
  problem->setup.youngs_modulus = problem->youngs_modulus(problem->z0);
  std::string handles_key;
  const HandlesTerm* handles = find_handles_term(problem->spec, &handles_key);
  std::vector<std::vector<int>> handle_vertices;
  if (handles) handle_vertices = constrain_handles(scene, *problem, *handles, handles_key);
  require_supported(scene, problem->setup);

  problem->model = build_static_model(problem->setup, 1.0);
  problem->youngs_offset = problem->model->parameter_layout().at("youngs_modulus").offset;
  if (handles) attach_handles(*problem, *handles, handle_vertices);
  problem->parameterization = design_map(*problem);

  std::vector<ObjectivePtr> parts;
  std::vector<double> coefficients;
  for (const ObjectiveTermSpec& spec : problem->spec.objective) {
    problem->terms.push_back(build_term(scene, *problem, spec));
    parts.push_back(problem->terms.back().term);
    coefficients.push_back(problem->terms.back().coefficient);
  }
  for (std::size_t k = 0; k < extensions.objective_terms.size(); ++k) {
    const InverseExtensions::Term& extra = extensions.objective_terms[k];
    ObjectivePtr term = extra.make ? extra.make(*problem) : nullptr;
    if (!term)
      throw std::invalid_argument("the objective term '" + extra.name + "' was not made (no objective)");
    problem->terms.push_back(
        {"objective term '" + extra.name + "'", extra.name, extra.weight, extra.weight, term});
    parts.push_back(term);
    coefficients.push_back(extra.weight);
  }
  if (parts.empty()) throw_scene_error(scene, "inverse.objective", "the objective has no terms");
  problem->objective = std::make_shared<WeightedSum>(std::move(parts), std::move(coefficients));

  problem->functional = make_functional(*problem, problem->objective);
  problem->setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return problem;
}

FieldError field_error(const Mesh& mesh, const Eigen::VectorXd& field, const Eigen::VectorXd& truth) {
  const Eigen::ArrayXd volumes = element_volumes(mesh).cwiseAbs().array();
  const Eigen::ArrayXd difference = field.array() - truth.array();
  FieldError error;
  error.relative_l2 =
      std::sqrt((volumes * difference.square()).sum() / (volumes * truth.array().square()).sum());
  error.max_relative = (difference.abs() / truth.array().abs()).maxCoeff();
  return error;
}

}  // namespace tailor
