#pragma once
// Linear (small-strain) homogenization of a periodic cell (docs/homogenization.md):
//   u(X) = eps_bar X + u~(X),  u~ periodic,  min over u~ of the cell energy,
//   C^H_IJ = (1/|Y|) u_I^T K u_J  for the unit macro strains eps_bar = e_I (Voigt),
// the energy form of the effective tensor (it equals the volume-averaged stress of load case J
// in component I at equilibrium). All load cases share one CHOLMOD factorization of the
// periodic stiffness matrix S^T K S.
//
// Voigt convention: 2D (11, 22, 12), 3D (11, 22, 33, 23, 13, 12); strains with engineering
// shear (gamma_12 = 2 eps_12), stresses plain, so sigma = C eps and the energy density is
// 1/2 eps^T C eps. Units: C^H in the units of the Young's moduli given.
#include <memory>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/homogenization/periodic_cell.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {

class ReducedAssembler;

// 2D only: the existing triangle elements are plane strain. Plane stress is obtained exactly by
// giving each element the plane-strain constants (E', nu') = (E (1 + 2 nu) / (1 + nu)^2,
// nu / (1 + nu)), whose in-plane Lame constants are the plane-stress ones
// lambda* = E nu / (1 - nu^2), mu = E / (2 (1 + nu)).
enum class PlaneMode { plane_strain, plane_stress };

struct LinearHomogenization {
  Matrix stiffness;             // C^H (Voigt), 3 x 3 in 2D, 6 x 6 in 3D
  std::vector<Vector> states;   // per load case: positions x = X + eps_I X + u~_I
  double symmetry_error = 0.0;  // max |C - C^T| / max |C| (round-off)
  double assembly_seconds = 0.0;
  double factorization_seconds = 0.0;
  double solve_seconds = 0.0;  // all load cases (solves + the tensor)
};

// The Voigt size of a dimension: 3 (2D), 6 (3D).
int voigt_size(int dim);
// The macro displacement gradient (symmetric strain tensor) of unit Voigt strain I.
Matrix unit_macro_strain(int dim, int voigt_index);

class LinearCell {
 public:
  // Throws std::invalid_argument for plane_stress with a 3D cell.
  LinearCell(PeriodicCell cell, PlaneMode mode = PlaneMode::plane_strain);
  ~LinearCell();
  LinearCell(const LinearCell&) = delete;
  LinearCell& operator=(const LinearCell&) = delete;

  const PeriodicCell& cell() const { return cell_; }
  int num_elements() const { return cell_.mesh.num_elements(); }
  PlaneMode plane_mode() const { return mode_; }

  // Solves the voigt_size(dim) cell problems for per-element Young's moduli and Poisson's
  // ratios (physical values; sizes num_elements()). Throws std::invalid_argument on bad sizes
  // or values, std::runtime_error when the factorization fails.
  LinearHomogenization solve(const Vector& youngs_modulus, const Vector& poisson_ratio);

  // Adjoint contraction after solve(): with W = dJ/dC^H (Voigt, any square matrix), returns
  // dJ/dE_e = sum_IJ W_IJ dC_IJ/dE_e = (1/|Y|) sum_IJ W_IJ u_I^T (dK/dE_e) u_J (the cell
  // problems are self-adjoint: the fluctuations' sensitivities drop out by equilibrium).
  Vector youngs_modulus_gradient(const Matrix& dJ_dC) const;

  // Forward and adjoint sensitivities of the cell problems after solve(), through the factor
  // of that solve (one back-solve each). state_tangent returns du_I = (du_I/dE) dE, the change
  // of load case I's state (full coordinates, per vertex) along per-element changes dE of the
  // physical Young's moduli: K du_I = -(d^2 E / dx dE) dE. state_tangent_transpose returns
  // (du_I/dE)^T w per element for a w of the state's size.
  Vector state_tangent(int load_case, const Vector& youngs_modulus_change) const;
  Vector state_tangent_transpose(int load_case, const Vector& w) const;
  // The physical Young's moduli of the last solve (empty before the first): a caller that
  // shares the cell checks with it that the factor is the one it needs.
  const Vector& solved_youngs_modulus() const { return youngs_modulus_; }

  // Per-element stress (row-major dim*dim) of load case I of the last solve (plane-strain
  // in-plane stress in 2D; for plane stress the in-plane stress of the plate).
  Matrix element_stresses(int load_case) const;

 private:
  PeriodicCell cell_;
  PlaneMode mode_;
  std::unique_ptr<Model> model_;
  const EnergyTerm* elastic_ = nullptr;
  std::unique_ptr<ReducedAssembler> assembler_;
  SparseMatrix hessian_;
  SparseCholesky factor_;
  Vector rest_;           // X (flattened)
  Vector parameters_;     // [E' per element, nu' per element] of the last solve
  Vector modulus_scale_;  // dE'/dE per element
  Vector youngs_modulus_;  // E per element of the last solve (physical)
  std::vector<Vector> states_;
};

}  // namespace tailor
