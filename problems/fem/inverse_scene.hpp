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
#include <vector>

#include "adjoint/taylor_test.hpp"
#include "objectives/material_smoothness.hpp"
#include "optimizers/optimizer.hpp"
#include "problems/fem/inverse_handles_spec.hpp"
#include "problems/fem/objective_term_registry.hpp"
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

// inverse.design.reduction.domains: the domains of a "domains" or "overlapping" basis.
struct DomainBasisSpec {
  int count = 4;                  // METIS domains
  bool from_regions = false;      // or the mesh's element regions
  int fixed_interface_modes = 6;  // per domain
  int derivative_modes = 3;       // per domain
  int interface_modes = 12;       // 0 = every interface DOF
  int overlap_layers = 2;         // "overlapping" only
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
  // Order k of the Krylov recurrence of the static response (krylov_recurrence.hpp) whose
  // blocks 2..k are added for nonlinear materials: 2 = the modal derivatives.
  int krylov_order = 2;
  // "basis": which displacement basis (docs/reduction.md, "Local reduced models"): "global" (the
  // candidates above), "domains" (Craig-Bampton per domain, plus the static responses) or
  // "overlapping" (the global candidates blended by principal-direction weights).
  std::string basis = "global";
  DomainBasisSpec domains;
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

// One entry of the "objective" list: its type (problems/fem/objective_term_registry.hpp), the
// settings the type parsed (copies of the spec share them), its JSON and its weight.
struct ObjectiveTermSpec {
  std::shared_ptr<const ObjectiveTermType> kind;
  std::shared_ptr<ObjectiveTermSettings> settings;  // null for a type without parse
  nlohmann::json value;                             // the whole term object
  double weight = 1.0;
  std::string key;  // "inverse.objective[i]"
  const std::string& type() const { return kind->type; }
  bool is_data() const { return kind->is_data; }  // compares displacements or forces
  // The settings as the type's own struct (builtin_terms.hpp, HandlesTerm), or null.
  template <class Settings>
  Settings* settings_as() const {
    return dynamic_cast<Settings*>(settings.get());
  }
};

struct InverseSpec {
  DesignSpec design;
  std::vector<ObjectiveTermSpec> objective;  // at least one data term
  std::optional<ModulusField> ground_truth;
  OptimizerOptions optimizer;   // progress is set by the caller
  TaylorTestOptions gradcheck;  // seed, initial_step, halvings
};

}  // namespace tailor
