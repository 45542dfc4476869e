#pragma once
// Density filter of a periodic cell (Bruns & Tortorelli 2001; Bourdin 2001): the physical
// density of element e is a weighted mean of the design densities around it,
//   rho_e = sum_f w_ef V_f z_f / sum_f w_ef V_f,  w_ef = max(0, r - |c_e - c_f|_Y),
// with |.|_Y the distance to the nearest periodic image (the filter wraps around the cell).
// The radius r is the minimum length scale of the design: features thinner than about r
// (checkerboards, one-element hinges) are smoothed out.
#include "forward/core/types.hpp"
#include "forward/homogenization/periodic_cell.hpp"

namespace tailor {

class DensityFilter {
 public:
  // Throws std::invalid_argument for r <= 0 or r larger than half the shortest lattice vector.
  DensityFilter(const PeriodicCell& cell, double radius);
  double radius() const { return radius_; }
  Vector apply(const Vector& design) const { return weights_ * design; }  // rho = W z
  Vector apply_transpose(const Vector& gradient) const { return weights_.transpose() * gradient; }  // W^T g
  const SparseMatrix& weights() const { return weights_; }

 private:
  double radius_;
  SparseMatrix weights_;  // rows sum to 1
};

}  // namespace tailor
