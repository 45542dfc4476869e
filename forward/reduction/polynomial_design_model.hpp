#pragma once
// The reduced design model of StVK and linear materials: W(q; w) = 1/2 s(q)^T G(w) s(q),
// s(q) = [q; (q_a q_b)_{a <= b}] (or q alone for linear materials), G(w) = G_0 + sum_j w_j G_j,
// with the coefficients of reduced_stvk_coefficients (forward/reduction/reduced_stvk.hpp). Exact;
// every evaluation costs O((r + P)^2) per coefficient matrix, P = r (r + 1) / 2.
#include <vector>

#include "forward/reduction/reduced_design_model.hpp"

namespace tailor {

class PolynomialDesignModel final : public ReducedDesignModel {
 public:
  // r = load size; the matrices are r x r or (r + P) x (r + P). Throws std::invalid_argument
  // (prefixed by `context`) for inconsistent sizes or no mode.
  PolynomialDesignModel(Matrix base, std::vector<Matrix> modes, int r,
                        const std::string& context = "PolynomialDesignModel");
  std::string name() const override { return "polynomial"; }
  int size() const override { return r_; }
  int design_size() const override { return static_cast<int>(modes_.size()); }
  void evaluate(const Vector& q, const Vector& w, double* energy, Vector* force, Matrix* stiffness) const override;
  AtDesign at_design(const Vector& w) const override;  // G(w) formed once
  Matrix force_design_derivative(const Vector& q) const override;
  // -> [lambda; J_s lambda]^T G_j s(q), O(m (r + P)^2).
  Vector force_design_derivative_transpose(const Vector& q, const Vector& lambda) const override;

  Matrix coefficients(const Vector& w) const;  // G(w)
  const Matrix& base() const { return base_; }
  const std::vector<Matrix>& modes() const { return modes_; }
  bool quadratic() const { return quadratic_; }  // pairs present (StVK)

 private:
  Matrix base_;
  std::vector<Matrix> modes_;
  int r_ = 0;
  bool quadratic_ = false;
};

}  // namespace tailor
