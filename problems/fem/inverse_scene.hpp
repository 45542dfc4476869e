#pragma once
// The optional "inverse" section of a scene as typed data: which parameter is designed and
// how it maps to design variables, the objective terms, the ground truth for error reports,
// and the optimizer and gradient-check settings (see docs/scenes.md). Parsed and
// validated with the rest of the scene (parse_scene); checks that need the mesh happen when
// the inverse problem is built (inverse_problem.hpp), naming the key path kept here.
#include <Eigen/Core>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "adjoint/taylor_test.hpp"
#include "objectives/material_smoothness.hpp"
#include "optimizers/optimizer.hpp"
#include "problems/fem/inverse_handles_spec.hpp"
#include "problems/fem/scene.hpp"

namespace tailor {

// A sphere inside which a modulus field is multiplied by `factor` (at element centroids).
struct ModulusInclusion {
  Eigen::VectorXd center;
  double radius = 0.0;
  double factor = 1.0;
};

// A per-element Young's modulus field: one value everywhere, one per materials[] entry (for
// its elements), one per mesh element from a file (whitespace-separated, element order), or
// an expression at element centroids c: value * (1 + gradient . c) * (factor of every
// inclusion holding c).
struct ModulusField {
  double value = 0.0;                // used when both lists are empty
  std::vector<double> per_material;  // from {"materials": [...]}
  std::vector<double> values;        // from {"file": path}
  Eigen::VectorXd gradient;          // relative change per unit length; empty = none
  std::vector<ModulusInclusion> inclusions;
  std::string key;  // JSON key path
};

// modes: E (or log E) = Phi z over the r lowest Laplacian material modes (inverse_modes.hpp).
enum class DesignGranularity { per_element, per_region, per_material, modes };
enum class DesignMap { log, identity };  // z = log E, or z = E
std::string to_string(DesignGranularity granularity);
std::string to_string(DesignMap map);

// "inverse.design.reduction": the design loop in reduced displacements and reduced materials
// (problems/fem/reduced_design.hpp, docs/reduction.md). The material is E = E0 (1 + sum_j w_j y_j)
// over the granularity's material modes y_j, linear in w, so the reduced StVK coefficients are
// precomputed exactly once per mode.
// A cubature rule for the reduced energy of materials without a polynomial reduced form
// (forward/reduction/cubature.hpp; problems/fem/reduced_design_cubature.hpp).
struct CubatureSpec {
  int elements = 120;       // the rule's elements at most
  int training_poses = 24;  // displacement poses the rule is fitted on
  double tolerance = 1e-3;  // relative training error at which the greedy fit stops
  int candidates = 0;       // elements scored per greedy step (a random subset); 0: every element
};

struct ReductionSpec {
  int displacement_modes = 6;     // linear vibration modes of the constrained mesh
  bool modal_derivatives = true;  // of the modes and static responses (none for linear materials)
  int derivative_modes = 3;       // how many of the lowest modes get derivatives (with the responses)
  bool static_responses = true;   // K^-1 f per handle force (and the other loads)
  bool design_responses = true;   // -K^-1 K_j u0 per material mode j (u0: the static response)
  double smoothness = 0.0;        // rho_j = smoothness * lambda_j on 1/2 sum_j rho_j w_j^2
  bool full_space_check = true;   // re-solve the final design in full space
  // While the full-space handle error exceeds full_space_tolerance, at most `refinements` times:
  // add the full-space equilibrium and its design sensitivities at the design to the basis,
  // precompute again and continue from the design.
  int refinements = 2;
  double full_space_tolerance = 0.01;
  // Positivity: E / E0 >= eps is kept by a C2 penalty kappa/3 sum_e v_e ((eps - E_e/E0_e)_+ / eps)^3
  // (v_e volume fractions), and E <= 0 is an infeasible point.
  double min_relative_modulus = 0.05;  // eps in (0, 1)
  double positivity_weight = 1.0;      // kappa
  // Given: the reduced energy is integrated by cubature (any material); absent: the exact
  // polynomial for StVK and linear materials, cubature with the defaults for the others.
  std::optional<CubatureSpec> cubature;
  std::string key;  // "inverse.design.reduction"
};

struct DesignSpec {
  std::string parameter = "youngs_modulus";  // the only designable parameter for now
  DesignGranularity granularity = DesignGranularity::per_element;
  DesignMap map = DesignMap::log;
  std::optional<double> min, max;  // bounds on E (not on z)
  std::optional<double> initial;   // E everywhere at the start; default: the scene's materials
  // granularity modes only:
  std::optional<int> modes;  // r, the number of material modes; nullopt = "full" (one per element)
  AdjacencyWeighting mode_weighting = AdjacencyWeighting::facet_over_distance;
  int output_modes = 0;                    // the first this many modes are written to result.vtu
  std::optional<ReductionSpec> reduction;  // the reduced design loop (granularity modes only)
  // One design variable per region or material (the report lists their values).
  bool grouped() const {
    return granularity == DesignGranularity::per_region || granularity == DesignGranularity::per_material;
  }
};

// Data terms compare displacements u of some vertices with wanted ones u*; the term is the
// relative misfit 1/2 |u - u*|^2 / |u*|^2 (see inverse_problem.hpp).
//
// Adding a term type: a struct here with its JSON "type" (kType) and whether it compares data
// (kIsData), an alternative in ObjectiveTerm, a parse_term_body overload (inverse_scene.cpp)
// and a build_term overload (inverse_problem.cpp). A missing overload fails to compile. A program
// adds its own types without touching these files: register_objective_term
// (problems/fem/objective_term_registry.hpp), parsed into a RegisteredTerm below.
struct TargetDisplacementsTerm {
  static constexpr const char* kType = "target_displacements";
  static constexpr bool kIsData = true;
  VertexSelector vertices;
  Eigen::VectorXd displacement;  // the same target for every selected vertex
};
struct ObservationsTerm {
  static constexpr const char* kType = "observations";
  static constexpr bool kIsData = true;
  std::string file;               // resolved path, for messages
  std::vector<int> vertices;      // one per line, distinct
  Eigen::MatrixXd displacements;  // one row per line, 2 or 3 columns
};
struct SyntheticObservationsTerm {
  static constexpr const char* kType = "synthetic_observations";
  static constexpr bool kIsData = true;
  VertexSelector vertices;
  ModulusField youngs_modulus;  // the truth the observations are simulated from
  double noise = 0.0;           // relative: std. deviation = noise * largest observed |u|
  unsigned seed = 1;
};
// Regularization of the designed per-element field E.
struct SmoothnessTerm {
  static constexpr const char* kType = "smoothness";
  static constexpr bool kIsData = false;
  bool logarithmic = true;  // penalize jumps of log E (ratios) rather than of E
  AdjacencyWeighting weighting = AdjacencyWeighting::unit;
};
struct TikhonovTerm {
  static constexpr const char* kType = "tikhonov";
  static constexpr bool kIsData = false;
  double prior = 1.0;  // J = 1/2 sum_e ((E_e - prior) / prior)^2
};

// A term of a type the program registered (problems/fem/objective_term_registry.hpp): its JSON,
// built into an Objective with the problem. (kType is no scene "type": the registered one is.)
struct ObjectiveTermType;
struct RegisteredTerm {
  static constexpr const char* kType = "(registered)";
  static constexpr bool kIsData = false;
  std::shared_ptr<const ObjectiveTermType> kind;
  nlohmann::json value;  // the whole term object
};

using ObjectiveTerm = std::variant<TargetDisplacementsTerm, ObservationsTerm, SyntheticObservationsTerm,
                                   SmoothnessTerm, TikhonovTerm, HandlesTerm, RegisteredTerm>;

struct ObjectiveTermSpec {
  ObjectiveTerm term;
  double weight = 1.0;
  std::string key;           // "inverse.objective[i]"
  std::string type() const;  // the JSON "type"
  bool is_data() const;      // compares displacements or forces (not a regularization)
};

struct InverseSpec {
  DesignSpec design;
  std::vector<ObjectiveTermSpec> objective;  // at least one data term
  std::optional<ModulusField> ground_truth;
  OptimizerOptions optimizer;   // progress is set by the caller
  TaylorTestOptions gradcheck;  // seed, initial_step, halvings
};

}  // namespace tailor
