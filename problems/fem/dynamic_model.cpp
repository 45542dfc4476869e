// build_dynamic_scene (problems/fem/dynamic_scene.hpp): the static scene's model plus inertia,
// gravity as a term of the densities, and Rayleigh damping.
#include "forward/fem/loads.hpp"
#include "problems/fem/dynamic_scene.hpp"
#include "problems/fem/linear_solver_choice.hpp"

namespace tailor {

DynamicSceneModel build_dynamic_scene(const Scene& scene) {
  const DynamicsSpec& spec = *scene.dynamics;
  DynamicSceneModel d;
  require_linear_elements(scene, "dynamics");
  d.setup = setup_static_scene(scene);
  const int dim = d.setup.dim(), m = d.setup.mesh.num_elements();
  for (std::size_t k = 0; k < scene.materials.size(); ++k)
    if (!(scene.materials[k].density > 0.0))
      throw SceneError(scene.source + ": " + scene.materials[k].key +
                       ".density: a dynamic scene needs a positive density");
  if (spec.initial_velocity && spec.initial_velocity->size() != dim)
    throw SceneError(scene.source + ": dynamics.initial_velocity: expected " + std::to_string(dim) +
                     " components");
  // Gravity becomes a GravityTerm of the density parameters (so that designs of the density
  // move the weight too) instead of part of the static setup's dead load.
  if (scene.loads.gravity)
    d.setup.nodal_forces -= gravity_forces(d.setup.mesh, d.setup.density, *scene.loads.gravity);
  d.model = build_static_model(d.setup, 1.0);
  d.rayleigh = spec.rayleigh_alpha > 0.0 || spec.rayleigh_beta > 0.0;
  d.terms = add_dynamics_terms(*d.model, d.setup.mesh,
                               DynamicsSetup{spec.lumping, scene.loads.gravity, d.rayleigh});
  d.p.resize(d.model->parameter_layout().size());
  d.p.head(2 * m) = d.setup.parameters();
  d.p.segment(d.terms.density_offset, m) = d.setup.density;
  if (d.rayleigh)
    d.p[d.terms.alpha_offset] = spec.rayleigh_alpha, d.p[d.terms.beta_offset] = spec.rayleigh_beta;
  d.options.scheme = spec.scheme;
  d.options.time_step = spec.time_step;
  d.options.newton.max_iterations = std::max(d.setup.solver.newton.max_iterations, 1);
  d.options.newton.hessian = d.setup.solver.newton.hessian;
  d.options.newton.reuse_factorization = d.setup.solver.newton.reuse_factorization;
  // solver.linear_solver (e.g. PETSc): every step's Newton solve and the transient adjoint's
  // backward solves go through it; empty keeps CHOLMOD with its factor reuse.
  d.options.newton.linear_solver = d.setup.solver.newton.linear_solver;
  d.rest = d.setup.rest_state();
  d.initial_velocities = Vector::Zero(d.rest.size());
  if (spec.initial_velocity)
    for (int v = 0; v < d.setup.mesh.num_vertices(); ++v)
      d.initial_velocities.segment(dim * v, dim) = *spec.initial_velocity;
  // Rest positions with the prescribed values on the fixed DOFs.
  d.initial_positions = d.model->elimination().expand(d.model->elimination().restrict_state(d.rest));
  // The rigid-body modes for algebraic multigrid, when whole vertices are free.
  if (d.options.newton.linear_solver)
    give_vertex_coordinates(*d.options.newton.linear_solver, d.model->elimination(), dim, d.rest);
  return d;
}

}  // namespace tailor
