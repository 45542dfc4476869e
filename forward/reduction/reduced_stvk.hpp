#pragma once
// Reduced Saint Venant-Kirchhoff model with exact polynomial precomputation (Barbic & James
// 2005, "Real-time subspace integration for St. Venant-Kirchhoff deformable models", section
// 3): for linear simplices the StVK energy of u = Phi q is a quartic polynomial in q, so its
// coefficients can be precomputed once and every later evaluation costs O(r^4), independent
// of the mesh.
//
// Form used here. Per element, the displacement gradient is linear in q, so are the linear
// strain L(q) = sym(grad u) and, in the pairs s = (q_a q_b)_{a <= b} (P = r (r + 1) / 2 of
// them), the quadratic part N(q) = grad u^T grad u of the Green strain E = L + N / 2. With the
// isotropic StVK density Psi = lambda/2 tr(E)^2 + mu tr(E^2) = 1/2 e^T W e over the
// independent strain components e, W = LL^T,
//
//   W(q) = sum_e V_e/2 |Lw^T (L_e q + N_e s / 2)|^2 = 1/2 w^T G w,    w = [q; s],
//
// with the symmetric (r + P)^2 coefficient matrix G = sum_e Y_e Y_e^T: its blocks are the
// quadratic (Phi^T K Phi), cubic and quartic coefficients of Barbic & James. The force is
// G_qq q + G_qs s + J_s^T (G_sq q + G_ss s) and the stiffness adds the second derivatives of
// s; both cost O((r + P) r^2) = O(r^4).
//
// Precomputation: one symmetric rank-k update per chunk of elements, in parallel (OpenMP),
// O(mesh size * r^4). Plane strain (2D) uses the same formulas (E_33 = 0).
#include <vector>

#include "forward/core/model.hpp"
#include "forward/reduction/reduced_elastic_model.hpp"

namespace tailor {

class ReducedStvk final : public ReducedElasticModel {
 public:
  // Precomputes from every ElasticTerm of the model, all of which must use the StVK material
  // (std::invalid_argument otherwise, or when the model has no elastic term); other terms
  // (loads) are ignored: reduced dynamics takes them as projected forces. basis: num_dofs x r
  // displacements from the mesh's rest positions; p: the parameters (Young's moduli and
  // Poisson's ratios are read per element).
  ReducedStvk(const Model& model, const Vector& p, const Matrix& basis);

  int size() const override { return r_; }
  void evaluate(const Vector& q, double* energy, Vector* force, Matrix* stiffness) const override;

  double precomputation_seconds() const { return precomputation_seconds_; }
  int precomputation_threads() const { return threads_; }
  // G, (r + P) x (r + P), symmetric; w = [q; (q_a q_b)_{a <= b}] with pairs in the order
  // (0,0), (0,1), ..., (0,r-1), (1,1), ...
  const Matrix& coefficients() const { return gram_; }

 private:
  int r_ = 0, pairs_ = 0;
  Matrix gram_;
  double precomputation_seconds_ = 0.0;
  int threads_ = 1;
};

// W, dW/dq and d2W/dq2 of W(q) = 1/2 w^T G w, w = [q; (q_a q_b)_{a <= b}], for a coefficient
// matrix G laid out as ReducedStvk::coefficients() (only its lower triangle is read).
void evaluate_stvk_polynomial(const Matrix& coefficients, const Vector& q, double* energy, Vector* force,
                              Matrix* stiffness);

// Coefficient matrices that are linear in per-element weights: with the Lame parameters of p,
// column j of element_weights (one row per mesh element) gives
//   G_j = sum_e element_weights(e, j) G_e(p),
// G_e the element's contribution to ReducedStvk::coefficients(). Since the StVK and linear
// energy densities are linear in Young's modulus at fixed Poisson's ratio, the coefficients of
// the moduli E_e = E0_e (c_0 + sum_j w_j y_je) are sum_j w_j G_j plus c_0 G_0 for weights
// E0-relative. Also accepts the linear material (the pair rows of its elements are zero: its
// energy is the quadratic form of the linear strain); std::invalid_argument for any other
// material (these need a cubature rule), a wrong size or a model without elastic terms.
// When every elastic term is linear the pair part vanishes and is not computed: the matrices
// are then r x r (W = 1/2 q^T G q); otherwise (r + P) x (r + P).
// Cost O(mesh * columns * (r + P)^2).
std::vector<Matrix> reduced_stvk_coefficients(const Model& model, const Vector& p, const Matrix& basis,
                                              const Matrix& element_weights);

}  // namespace tailor
