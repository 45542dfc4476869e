#pragma once
// Nonlinear homogenization of a periodic cell under an imposed macro deformation gradient F:
//   x(X) = F X + w(X),  w periodic,  w = argmin of the cell energy (any hyperelastic material),
// solved by Newton on the periodic elimination (forward/solve/newton.hpp). The macro first
// Piola-Kirchhoff stress is the volume average P = (1/|Y|) sum_e V_e P_e, which by the
// Hill-Mandel condition equals dW/dF of the macro energy density W = E/|Y| at equilibrium
// (the boundary forces' resultant per reference area). 2D is plane strain.
#include <memory>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/fem/material.hpp"
#include "forward/homogenization/periodic_cell.hpp"
#include "forward/solve/newton.hpp"

namespace tailor {

struct MacroResponse {
  Matrix deformation_gradient;  // F (dim x dim)
  Matrix stress;                // macro first Piola-Kirchhoff stress P (dim x dim), energy / volume units
  double energy_density = 0.0;  // W = E / |Y|
  NewtonResult newton;
};

class NonlinearCell {
 public:
  // Per-element Young's modulus and Poisson's ratio. Throws std::invalid_argument on bad sizes.
  NonlinearCell(PeriodicCell cell, MaterialKind material, const Vector& youngs_modulus,
                const Vector& poisson_ratio, NewtonOptions options = {});
  ~NonlinearCell();
  NonlinearCell(const NonlinearCell&) = delete;
  NonlinearCell& operator=(const NonlinearCell&) = delete;

  // Equilibrium at macro F, warm-started from the previous solution (load stepping is the
  // caller's: follow a path in small steps). Never throws for a failed Newton solve: see
  // response.newton.
  MacroResponse solve(const Matrix& deformation_gradient);
  const Vector& state() const { return state_; }  // positions of the last solve
  const PeriodicCell& cell() const { return cell_; }

 private:
  PeriodicCell cell_;
  std::unique_ptr<Model> model_;
  const EnergyTerm* elastic_ = nullptr;
  std::unique_ptr<NewtonSolver> newton_;
  Vector parameters_, fluctuation_, state_;
  double user_reference_residual_ = 0.0;
};

// The stress-strain curve along F(t) = I + t H for t = t_max k / steps, k = 0..steps (each
// point warm-started from the previous). Stops early (shorter result) when Newton fails.
std::vector<MacroResponse> macro_strain_path(NonlinearCell& cell, const Matrix& direction, double t_max,
                                             int steps);

}  // namespace tailor
