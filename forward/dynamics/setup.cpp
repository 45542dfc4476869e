#include "forward/dynamics/setup.hpp"

#include <stdexcept>

namespace tailor {

DynamicTerms add_dynamics_terms(Model& model, const Mesh& mesh, const DynamicsSetup& setup) {
  if (model.num_dofs() != mesh.dim() * mesh.num_vertices())
    throw std::invalid_argument("add_dynamics_terms: the model's DOFs do not match the mesh");
  DynamicTerms terms;
  ParameterLayout& layout = model.parameter_layout();
  terms.density_offset = layout.add("density", mesh.num_elements());
  auto mass = std::make_shared<const MassOperator>(mesh, setup.lumping, terms.density_offset);
  terms.inertia = &model.add(std::make_unique<InertiaTerm>(mass));
  if (setup.gravity)
    terms.gravity = &model.add(std::make_unique<GravityTerm>(mesh, *setup.gravity, terms.density_offset));
  if (setup.rayleigh) {
    if (!layout.contains("youngs_modulus") || !layout.contains("poisson_ratio"))
      throw std::invalid_argument(
          "add_dynamics_terms: Rayleigh damping needs the youngs_modulus and poisson_ratio blocks");
    terms.alpha_offset = layout.add("rayleigh_alpha", 1);
    terms.beta_offset = layout.add("rayleigh_beta", 1);
    terms.damping = &model.add(std::make_unique<RayleighDamping>(
        mesh, mass, terms.alpha_offset, terms.beta_offset, layout.at("youngs_modulus").offset,
        layout.at("poisson_ratio").offset));
  }
  return terms;
}

}  // namespace tailor
