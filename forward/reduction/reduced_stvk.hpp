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
  std::vector<int> pair_;  // r x r (row-major): index of the pair (min(a,b), max(a,b))
  double precomputation_seconds_ = 0.0;
  int threads_ = 1;
};

}  // namespace tailor
