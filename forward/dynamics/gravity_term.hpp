#pragma once
// The potential of gravity with the density as a parameter:
//   E(x, p) = - sum_e rho_e V_e / (d + 1) sum_{a in e} g . (x_a - X_a),
// rho_e = p[density_offset + e] [mass / volume], g the acceleration [length / time^2]: the
// consistent nodal forces of gravity_forces() (forward/fem/loads.hpp), here differentiable
// in the density. Measured from the rest positions X (a constant) so that the total potential
// stays small near equilibrium and Newton's line search can compare energies.
#include "forward/core/energy_term.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

class GravityTerm final : public EnergyTerm {
 public:
  GravityTerm(const Mesh& mesh, Eigen::VectorXd gravity, int density_offset);
  std::string name() const override { return "gravity"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  bool hessian_is_constant() const override { return true; }  // linear in x
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override;
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override;
  void add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                 Vector& gradient_p) const override;
  const Eigen::VectorXd& gravity() const { return gravity_; }

 private:
  // sum over the element's vertices of g . w_a, times V_e / (d + 1).
  double element_work(const Vector& w, int e) const;
  Eigen::VectorXd gravity_;
  int density_offset_;
  Eigen::MatrixXi elements_;
  Vector rest_;             // X, interleaved
  Eigen::VectorXd shares_;  // V_e / (d + 1)
};

}  // namespace tailor
