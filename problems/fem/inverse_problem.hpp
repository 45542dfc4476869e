#pragma once
// The inverse problem of a scene with an "inverse" section, built and checked against the
// mesh: the static setup at the initial design, the full-load model, the design map
// z -> p (Young's moduli per element, region or material, as log E or E, embedded into the
// full parameter vector with Poisson's ratios fixed), the objective (a WeightedSum of the
// scene's terms) and the reduced functional J(z) with its adjoint gradient.
//
// Data terms are relative misfits, 1/2 |u - u*|^2 / |u*|^2 over their vertices (u the
// displacements at equilibrium, u* the wanted or observed ones; |u*|^2 is replaced by
// n L^2, L the mesh's bounding-box diagonal, when every u* is zero), so a weight of 1 means the
// same in every scene and the optimizer's absolute tolerances carry over between scenes.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "adjoint/static_functional.hpp"
#include "optimizers/optimizer.hpp"
#include "problems/fem/inverse_modes.hpp"
#include "problems/fem/inverse_scene.hpp"
#include "problems/fem/static_scene.hpp"

namespace tailor {

struct HandleDesign;  // problems/fem/inverse_handles.hpp

// One term of the objective: the objective adds coefficient * term.
struct ObjectiveTermInfo {
  std::string key;   // "inverse.objective[i]"
  std::string type;  // its "type"
  double weight = 1.0;
  double coefficient = 1.0;  // weight / the scale its build returned (|u*|^2 for data terms)
  ObjectivePtr term;
};

struct InverseProblem {
  std::string scene_name, scene_source;
  InverseSpec spec;
  StaticSetup setup;             // youngs_modulus holds the initial design; fixed_dofs include the handles'
  std::unique_ptr<Model> model;  // at full load
  int youngs_offset = 0;         // of the "youngs_modulus" block in p
  Eigen::VectorXi design_of_element;  // per element: its design variable (not for modes)
  // Per material variable: "element e", "region r", "materials[m]", "mode j".
  std::vector<std::string> design_labels;
  std::optional<ModalDesign> modal;  // granularity modes: Phi, y0 and z -> E
  // A program's own design map z -> E per element (InverseExtensions::element_map); it replaces
  // the granularity's. design_values are then z itself, labelled "z[k]".
  ParameterizationPtr element_map;
  ParameterizationPtr parameterization;
  std::vector<ObjectiveTermInfo> terms;
  ObjectivePtr objective;
  std::unique_ptr<StaticFunctional> functional;
  // With a "handles" term: the handle displacements u~ appended to the design, z = [material
  // design, u~ / scale], with their objective (problems/fem/inverse_handles.hpp).
  std::shared_ptr<const HandleDesign> handles;
  Vector z0;                   // initial design
  Bounds bounds;               // in z-space; empty when the design has no min/max
  Eigen::VectorXd truth;       // per element true E; empty when unknown
  std::string truth_key;       // the key it came from
  double setup_seconds = 0.0;  // building all this, including the synthetic forward solves

  int num_design() const { return static_cast<int>(z0.size()); }  // all of z
  int num_material_design() const { return static_cast<int>(design_labels.size()); }
  // E per material design variable (modes: per element).
  Eigen::VectorXd design_values(const Vector& z) const;
  Eigen::VectorXd youngs_modulus(const Vector& z) const;  // E per element
  // The static setup at design z: its Young's moduli and, with handles, u~ prescribed on the
  // handle DOFs (solve_static of it is the equilibrium J(z) sees).
  StaticSetup setup_at(const Vector& z) const;
};

// What a program adds to a scene's inverse problem in C++ (problems/fem/study.hpp composes it).
struct InverseExtensions {
  // Energy terms added to every model of the problem (StaticSetup::extra_terms).
  std::vector<EnergyTermFactory> energy_terms;
  // Objective terms added after the scene's: weight * make(problem), made once the model and
  // the design map exist.
  struct Term {
    std::string name;  // its "type" in reports
    double weight = 1.0;
    std::function<ObjectivePtr(const InverseProblem& problem)> make;
  };
  std::vector<Term> objective_terms;
  // A design map z -> E per element instead of the scene's granularity and map, with its start
  // and bounds (in z; empty: none). The scene's design min/max/initial do not apply then.
  ParameterizationPtr element_map;
  Vector z0;
  Bounds bounds;
};

// Throws SceneError (no inverse section, selectors that select nothing, sizes that do not fit
// the mesh, an initial design outside the bounds, a synthetic forward solve that fails, ...)
// and MeshError; std::invalid_argument for extensions that do not fit (a map of the wrong size).
std::unique_ptr<InverseProblem> build_inverse_problem(const Scene& scene,
                                                      const InverseExtensions& extensions = {});

// The reduced functional J(z) = objective(x*(p(z)), p(z)) on the problem's model and design,
// with the Newton settings the problem's own functional uses (its objective is problem.objective).
std::unique_ptr<StaticFunctional> make_static_functional(const InverseProblem& problem,
                                                         ObjectivePtr objective);

// The per-element values of a Young's modulus field given in the scene (SceneError naming
// field.key when it does not fit the mesh or is not > 0 somewhere).
Eigen::VectorXd modulus_field_values(const Scene& scene, const StaticSetup& setup, const ModulusField& field);
// Records `truth` (per element) as the problem's true Young's modulus; a second source must agree
// with the first (SceneError naming `key` otherwise).
void set_truth(const Scene& scene, InverseProblem& problem, const Eigen::VectorXd& truth, const std::string& key);

// Errors of a per-element field against the truth: the volume-weighted relative L2 error
// sqrt(sum_e V_e (E_e - T_e)^2 / sum_e V_e T_e^2) and the largest |E_e - T_e| / T_e.
struct FieldError {
  double relative_l2 = 0.0;
  double max_relative = 0.0;
};
FieldError field_error(const Mesh& mesh, const Eigen::VectorXd& field, const Eigen::VectorXd& truth);

}  // namespace tailor
