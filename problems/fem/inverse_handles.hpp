#pragma once
// The "handles" term of an inverse scene against the mesh (heterogeneous material design, Xu,
// Li, Chen, Barbic 2015; docs/methods.md section 5). Handle vertices become prescribed DOFs whose
// displacements u~ are design variables appended after the material design, z = [z_E, u~];
// the objective is a HandleObjective whose reactions come from copies of the elastic terms
// restricted to the elements touching the handles (plus the loads on handle vertices).
#include <memory>
#include <string>
#include <vector>

#include "adjoint/parameterization.hpp"
#include "objectives/handle_objective.hpp"
#include "problems/fem/inverse_problem.hpp"

namespace tailor {

// The handles term's part of an inverse problem (InverseProblem::handles): its objective (also
// in InverseProblem::terms), where u~ sits in the parameters p, and the characteristic
// displacement `scale`: the optimizer sees u~ / scale, so those variables are O(1) like log E.
struct HandleDesign {
  std::shared_ptr<const HandleObjective> objective;
  int offset = 0;                                              // of the "handle_displacement" block u~ in p
  double scale = 1.0;                                          // u~ = scale * z_u
  int size() const { return objective->displacement_size(); }  // entries of u~
  // The block of the design map: u~ = scale * z_u at `offset`.
  ParameterBlock parameter_block() const;
  // u~ = scale * z_u as the prescribed displacement of the handle DOFs in `setup`.
  void prescribe(const Vector& z_u, StaticSetup& setup) const;
};

// The handles term of the spec, or null.
const HandlesTerm* find_handles_term(const InverseSpec& spec, std::string* key = nullptr);

// Before the model is built: resolves the handle vertices, adds their DOFs to
// problem.setup.fixed_dofs (prescribed displacement 0; u~ comes through the parameters) and
// checks that supports and handles together pin every rigid motion. Returns each handle's
// vertices (increasing). Throws SceneError (a vertex in two handles or in a Dirichlet set, a force or
// displacement of the wrong size, rigid motion left free).
std::vector<std::vector<int>> constrain_handles(const Scene& scene, InverseProblem& problem,
                                                const HandlesTerm& term, const std::string& key);

// After the model is built: adds the "handle_displacement" block to the model, sets
// problem.handles, and appends u~0 / scale to problem.z0 (u~0: ubar, or for handles
// without ubar the displacement of their vertices at the initial design when they are free and
// apply fbar as a load; zero when that solve fails) and unbounded entries to problem.bounds.
// scale: the largest |ubar|, else the largest |u~0| of a vertex, else 1e-3 of the mesh's
// bounding-box diagonal.
void attach_handles(InverseProblem& problem, const HandlesTerm& term,
                    const std::vector<std::vector<int>>& vertices);

// What a handle achieved at a design: forces at the equilibrium, displacements u~.
struct HandleResult {
  std::string key;  // "inverse.objective[i].handles[h]"
  int vertices = 0;
  double weight = 1.0;
  Vector total_force;   // the total force the handle applies to the body
  Vector target_force;  // fbar as given (total, or per vertex when force_per_vertex); empty when none
  bool force_per_vertex = false;
  double force_error = 0.0;           // max over the entries' vertices of |f - fbar| (the total: one entry)
  double relative_force_error = 0.0;  // force_error / |fbar| (per vertex: / |fbar per vertex|)
  Vector displacement;                // mean of u~ over the handle's vertices
  Vector target_displacement;         // ubar; empty when none
  double displacement_error = 0.0;    // max over the vertices of |u~_v - ubar|
  double relative_displacement_error = 0.0;  // displacement_error / |ubar|
};
// `positions`: the equilibrium at z (full state). Empty without handles.
std::vector<HandleResult> handle_results(const InverseProblem& problem, const Vector& z,
                                         const Vector& positions);

}  // namespace tailor
