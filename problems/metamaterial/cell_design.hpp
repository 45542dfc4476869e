#pragma once
// Density-based design of a periodic cell (docs/homogenization.md, "Inverse design"):
//   z (per element, in [0, 1])  --filter-->  rho~ = W z  --projection-->  rho = H_beta(rho~)
//   --SIMP-->  E_e = E_min + rho_e^p (E_0 - E_min)
//   --cell problems-->  C^H(E)  -->  J(C^H)
// with a fixed Poisson's ratio nu_0 for every element. dJ/dz = W^T (H' dE/drho dJ/dE), and
// dJ/dE from the self-adjoint cell problems (LinearCell::youngs_modulus_gradient). H_beta is
// the smoothed Heaviside projection of Wang, Lazarov & Sigmund 2011 (Struct. Multidisc.
// Optim. 43, eq. 9) with threshold 1/2,
//   H(t) = (tanh(beta/2) + tanh(beta (t - 1/2))) / (2 tanh(beta/2)),
// off (H(t) = t) when beta = 0; raising beta in stages drives the design to 0/1.
#include <memory>
#include <string>
#include <vector>

#include "adjoint/reduced_functional.hpp"
#include "forward/homogenization/linear_homogenization.hpp"
#include "problems/metamaterial/density_filter.hpp"

namespace tailor {

struct SimpMaterial {
  double youngs_modulus = 1.0;       // E_0 of the solid
  double poisson_ratio = 0.3;        // nu_0 of the solid (and the void)
  double min_youngs_modulus = 1e-3;  // E_min (void), > 0
  double penalty = 3.0;              // p
};

// Objectives on the effective tensor (any combination, summed).
struct CellObjective {
  // Target C^H entries: sum_k weight_k (C_{i_k j_k} - value_k)^2 / scale^2.
  struct Entry {
    int row, col;
    double value, weight = 1.0;
  };
  std::vector<Entry> entries;
  double entry_scale = 1.0;
  // Directional stiffness (docs/methods.md section 12): T = 1/(2n) sum_i (E_H(d_i) / E_tar,i - 1)^2.
  std::vector<Vector> directions;
  std::vector<double> target_moduli;
  double directional_weight = 1.0;
  // Poisson's ratio: 1/2 sum_k (nu(d_k, n_k) - target)^2 over the pairs given.
  std::vector<std::pair<Vector, Vector>> poisson_pairs;
  double poisson_target = 0.0;
  double poisson_weight = 1.0;

  // J(C) and, when dJ_dC is non-null, dJ/dC (same size as C).
  double evaluate(const Matrix& stiffness, Matrix* dJ_dC) const;
};

class CellDesignFunctional final : public ReducedFunctional {
 public:
  CellDesignFunctional(std::shared_ptr<LinearCell> cell, SimpMaterial material, double filter_radius,
                       CellObjective objective);
  int size() const override { return cell_->num_elements(); }
  double value(const Vector& z) override;
  double value_and_gradient(const Vector& z, Vector& gradient) override;

  // Volume fraction of the filtered density, sum V_e rho_e / |Y|, and its gradient in z.
  double volume_fraction(const Vector& z, Vector* gradient) const;
  // Physical (filtered, projected) densities.
  Vector densities(const Vector& z) const;
  void set_projection(double beta);  // beta >= 0; 0 switches the projection off
  double projection() const { return beta_; }
  Vector youngs_moduli(const Vector& rho) const;
  const DensityFilter& filter() const { return filter_; }
  // The last solve's result (after value / value_and_gradient).
  const LinearHomogenization& last() const { return last_; }

 private:
  double evaluate(const Vector& z, Vector* gradient);
  std::shared_ptr<LinearCell> cell_;
  SimpMaterial material_;
  DensityFilter filter_;
  CellObjective objective_;
  Eigen::VectorXd volumes_;
  double beta_ = 0.0;
  LinearHomogenization last_;
};

}  // namespace tailor
