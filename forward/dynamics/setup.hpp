#pragma once
// Adds the dynamic terms to a Model over a mesh, with their parameter blocks:
//   "density" (one per element, [mass / volume]), and with Rayleigh damping
//   "rayleigh_alpha" (1, [1/time]) and "rayleigh_beta" (1, [time]).
// The elastic term's "youngs_modulus" and "poisson_ratio" blocks must already exist when
// Rayleigh damping is requested (its K is the rest stiffness of those moduli).
#include <optional>

#include "forward/core/model.hpp"
#include "forward/dynamics/gravity_term.hpp"
#include "forward/dynamics/inertia_term.hpp"
#include "forward/dynamics/rayleigh_damping.hpp"

namespace tailor {

struct DynamicsSetup {
  MassLumping lumping = MassLumping::consistent;
  std::optional<Eigen::VectorXd> gravity;  // acceleration [length / time^2]; none: no gravity term
  bool rayleigh = false;
};

struct DynamicTerms {
  InertiaTerm* inertia = nullptr;
  GravityTerm* gravity = nullptr;      // null without gravity
  RayleighDamping* damping = nullptr;  // null without Rayleigh damping
  int density_offset = -1, alpha_offset = -1, beta_offset = -1;
};

DynamicTerms add_dynamics_terms(Model& model, const Mesh& mesh, const DynamicsSetup& setup);

}  // namespace tailor
