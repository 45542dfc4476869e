#pragma once
// The reduced design loop of a handle scene (Xu, Li, Chen, Barbic, "Interactive material design
// using model reduction", TOG 2015; docs/reduction.md, "Reduced design loop"), chosen by
// "inverse.design.reduction":
//  - material: E = E0 (1 + sum_j w_j y_j) over the granularity's m Laplacian material modes,
//    y_j scaled to O(1) (y_j = sqrt(total volume) phi_j; y_1 = 1, a uniform scaling);
//  - displacements: u = Phi q over a mass-orthonormal basis of the static responses to the
//    handle forces (and the other loads), the linear vibration modes of the constrained mesh,
//    the design responses -K^-1 K_j u0 and the modal derivatives of the modes and responses
//    (nonlinear materials);
//  - the handles are free vertices loaded with their forces fbar; the objective is their
//    mean displacement's misfit 1/2 sum_h W_h |mean_v u_v - ubar_h|^2 / |ubar_h|^2 plus
//    1/2 smoothness sum_j lambda_j w_j^2 (lambda_j the modes' Laplacian eigenvalues);
//  - per optimizer iteration: Newton in q and the adjoint gradient in w, O(m (r + P)^2),
//    independent of the mesh (adjoint/reduced_equilibrium_functional.hpp); for materials
//    other than StVK and linear (or with inverse.design.reduction.cubature) the reduced
//    energy is integrated by a cubature rule instead, O(|C| r^2)
//    (problems/fem/reduced_design_cubature.hpp);
//  - at the end, the design is solved again in full space and the reduced and full handle
//    errors are reported side by side.
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "adjoint/reduced_equilibrium_functional.hpp"
#include "optimizers/optimizer.hpp"
#include "problems/fem/inverse_scene.hpp"
#include "problems/fem/reduced_design_cubature.hpp"
#include "problems/fem/scene.hpp"
#include "problems/fem/static_scene.hpp"

namespace tailor {

struct ReducedDesignHandle {
  std::string key;  // "inverse.objective[i].handles[h]"
  std::vector<int> vertices;
  Eigen::VectorXd force;   // total over the vertices
  Eigen::VectorXd target;  // ubar
  double weight = 1.0;
};

struct ReducedDesignTimings {
  double setup = 0.0;  // scene, model, mass
  double displacement_modes = 0.0;
  double responses = 0.0;  // static and design responses
  double modal_derivatives = 0.0;
  double material_modes = 0.0;
  double coefficients = 0.0;  // the reduced StVK coefficients of G_0 and every mode (last pass)
  double cubature = 0.0;      // the cubature fit, instead of the coefficients (every pass)
  double refinement = 0.0;    // basis refinements (without their coefficients)
  double total = 0.0;
};

struct ReducedDesign {
  std::string scene_name, scene_source;
  ReductionSpec spec;
  StaticSetup setup;  // handles free, their forces among the loads; youngs_modulus = E0
  std::unique_ptr<Model> model;
  Matrix basis;                 // Phi, num_dofs x r, M-orthonormal
  SparseMatrix mass;            // the inner product of the basis
  int basis_candidates = 0;     // columns before orthonormalization dropped the dependent ones
  Matrix material_modes;        // y, num_elements x m
  Vector material_eigenvalues;  // lambda_j
  std::vector<ReducedDesignHandle> handles;
  std::unique_ptr<ReducedEquilibriumFunctional> functional;
  std::optional<ReducedDesignCubature> cubature;  // the rule of the last precomputation, if any
  ReducedDesignTimings timings;
  OptimizerOptions optimizer;

  int num_design() const { return static_cast<int>(material_modes.cols()); }
  Eigen::VectorXd youngs_modulus(const Vector& w) const;  // E0 (1 + y w), per element
  // Per handle: |mean_v u_v - ubar| / |ubar| (the mean over its vertices) for displacements u
  // (num_dofs).
  std::vector<double> handle_errors(const Vector& displacement) const;
  Vector reduced_displacement(const Vector& q) const { return basis * q; }
};

// Builds the reduced design of a scene with inverse.design.reduction. Throws SceneError for
// scene problems (no handles term, a handle without force or displacement, other objective
// terms) and std::invalid_argument naming inverse.design.reduction.cubature when the cubature
// rule cannot be fitted.
ReducedDesign build_reduced_design(const Scene& scene);

// Adds the full-space equilibrium displacement of design w and its sensitivities du/dw_j (at
// that equilibrium, exact tangent) to the basis, mass-orthonormalizes and precomputes the
// coefficients (or fits the cubature rule) again (a new functional). Returns the seconds spent.
double refine_basis(ReducedDesign& design, const Vector& w, const Vector& displacement);

// Gives the handles new target displacements ubar (one per handle, in design.handles' order)
// for the next run_reduced_design, without another precomputation: the basis (static and
// design responses to the handle forces, modes, derivatives, refinements), the coefficients and
// the cubature rule depend on the forces and the materials, not on the targets. This is what
// makes the loop interactive: move a target, design again in milliseconds per iteration.
// Throws std::invalid_argument for a wrong count or size, or a zero or non-finite target.
void set_handle_targets(ReducedDesign& design, const std::vector<Eigen::VectorXd>& targets);

struct FullSpaceCheck {
  bool converged = false;
  std::string message;
  double seconds = 0.0;
  double min_youngs_modulus = 0.0;
  std::vector<double> handle_errors;  // as ReducedDesign::handle_errors
  Vector displacement;                // num_dofs
};
// Solves the design w in full space (the scene's solver, handle forces as loads). With
// `start_displacement` (num_dofs, e.g. the reduced solution Phi q) Newton starts there at full
// load (a few iterations where the reduced model is close), falling back to the path from rest.
FullSpaceCheck full_space_check(const ReducedDesign& design, const Vector& w,
                                const Vector* start_displacement = nullptr);
// The same for any per-element field E (e.g. a full-space design's).
FullSpaceCheck full_space_solve(const ReducedDesign& design, const Eigen::VectorXd& youngs_modulus,
                                const Vector* start_displacement = nullptr);

// One reduced optimization (the first, then one after each basis refinement).
struct ReducedDesignPass {
  int reduced_size = 0, iterations = 0;
  double seconds = 0.0;
  double median_iteration_ms = 0.0;  // of this pass alone (its cost grows with reduced_size)
  std::string status;
  double reduced_error = 0.0, full_error = 0.0;  // largest over the handles (full: 0 without a check)
};

struct ReducedDesignRun {
  std::vector<ReducedDesignPass> passes;
  OptimizerResult result;
  std::vector<double> iteration_ms;  // per optimizer iteration (wall time between iterations)
  double median_iteration_ms = 0.0;
  Vector q;  // the reduced equilibrium at the best design
  std::vector<double> reduced_errors;
  std::optional<FullSpaceCheck> full;
  std::optional<ReducedDesignCubature> cubature;  // of the last pass
  ReducedDesignTimings timings;
  int reduced_size = 0, material_modes = 0, coefficient_width = 0, basis_candidates = 0;
  std::string report_path;
};

// Builds, minimizes from w = 0 with the scene's optimizer, checks in full space (unless
// reduction.full_space_check is false) and writes out_dir/report.json (kind "reduced_design").
// `progress`: one line per iteration with its milliseconds; `log`: a summary.
ReducedDesignRun run_reduced_design_scene(const Scene& scene, const std::string& out_dir,
                                          std::ostream* log = nullptr, std::ostream* progress = nullptr);
// The same for a design built already.
ReducedDesignRun run_reduced_design(ReducedDesign& design, const std::string& out_dir,
                                    std::ostream* log = nullptr, std::ostream* progress = nullptr);

}  // namespace tailor
