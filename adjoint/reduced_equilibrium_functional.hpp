#pragma once
// ReducedEquilibriumFunctional: material design with reduced displacements and reduced
// materials (Xu, Li, Chen, Barbic, "Interactive material design using model reduction", TOG
// 2015; docs/reduction.md, "Reduced design loop"). Displacements u = Phi q (r coordinates),
// the design w (one coordinate per material mode). For StVK (and linear) materials, whose
// energy density is linear in Young's modulus at fixed Poisson's ratio, the reduced energy is
//
//   W(q; w) = 1/2 s(q)^T G(w) s(q),   s(q) = [q; (q_a q_b)_{a <= b}],   G(w) = G_0 + sum_j w_j G_j,
//
// (forward/reduction/reduced_stvk.hpp, reduced_stvk_coefficients; with only linear materials
// s(q) = q and the G are r x r). The functional is
//
//   J(w) = 1/2 sum_i c_i (B q(w) - t)_i^2 + 1/2 sum_j rho_j w_j^2 (+ a positivity penalty),
//   q(w): dW/dq (q; w) = f      (reduced equilibrium, Newton in q),
//
// with the adjoint gradient
//
//   K(q) lambda = B^T C (B q - t),   dJ/dw_j = -[lambda; J_s lambda]^T G_j s(q) + rho_j w_j,
//
// K = d2W/dq2 (symmetric), J_s = ds_pairs/dq. Every evaluation costs O(m (r + P)^2 + r^3 ...),
// independent of the mesh (P = r (r + 1) / 2, m design coordinates).
//
// Other materials give no polynomial; a ReducedDesignModel (forward/reduction/
// reduced_design_model.hpp) then supplies W(q; w), its q-derivatives and the mixed term
// lambda^T d(dW/dq)/dw, e.g. a cubature rule (CubatureDesignModel); the gradient is the same
// adjoint formula, dJ/dw_j = -lambda^T d(dW/dq)/dw_j + rho_j w_j, at cost O(|C| r^2).
#include <memory>
#include <vector>

#include "adjoint/reduced_functional.hpp"
#include "forward/reduction/reduced_design_model.hpp"

namespace tailor {

struct ReducedEquilibriumData {
  // Either the polynomial coefficients (StVK, linear):
  Matrix base;                // G_0
  std::vector<Matrix> modes;  // G_j, one per design coordinate (same size as base)
  // or a model (base and modes empty then):
  std::shared_ptr<const ReducedDesignModel> model;
  Vector load;            // f, r
  Matrix rows;            // B, k x r: the observed displacement components
  Vector target;          // t, k
  Vector row_weights;     // c, k, >= 0
  Vector regularization;  // rho, m, >= 0 (empty: zero)
  // Optional positivity of the relative moduli e = 1 + Y w per element (Y: elements x m, empty:
  // none): the penalty kappa/3 sum_e v_e ((eps - e_e)_+ / eps)^3 (C2), and an evaluation
  // error where some e_e <= 0. This part costs O(elements * m) per evaluation (a product with
  // Y), the only one that grows with the mesh.
  Matrix element_modes;            // Y
  Vector element_weights;          // v_e (volume fractions), one per row of Y
  double positivity_floor = 0.05;  // eps, in (0, 1)
  double positivity_weight = 1.0;  // kappa >= 0
};

struct ReducedEquilibriumOptions {
  // Converged when |dW/dq - f| <= tolerance * max(|f|, |dW/dq|) (or the step is at round-off).
  double tolerance = 1e-12;
  int max_iterations = 60;
  bool warm_start = true;  // start Newton at the last equilibrium
};

// The part of J that does not depend on the displacements: 1/2 sum_j rho_j w_j^2 plus the
// positivity penalty of data.element_modes (when given); adds its gradient to `gradient` (when
// set, sized m). Throws EvaluationError where some relative modulus 1 + (Y w)_e <= 0. Shared
// with the full-space form of the same objective (problems/fem/full_space_design.hpp).
double design_terms(const ReducedEquilibriumData& data, const Vector& w, Vector* gradient);

class ReducedEquilibriumFunctional final : public ReducedFunctional {
 public:
  // Throws std::invalid_argument for inconsistent sizes or negative weights. Polynomial
  // coefficients move into a PolynomialDesignModel: data().model is always set.
  explicit ReducedEquilibriumFunctional(ReducedEquilibriumData data, ReducedEquilibriumOptions options = {});

  int size() const override { return model_->design_size(); }
  int reduced_size() const { return r_; }
  double value(const Vector& w) override;
  double value_and_gradient(const Vector& w, Vector& gradient) override;

  // G(w) (full symmetric matrix); std::invalid_argument when the model is not polynomial.
  Matrix coefficients(const Vector& w) const;
  const ReducedDesignModel& model() const { return *model_; }
  // W, dW/dq and d2W/dq2 at (q, w) (null pointers: not wanted).
  void evaluate(const Vector& q, const Vector& w, double* energy, Vector* force, Matrix* stiffness) const;
  // The reduced equilibrium at w (Newton from the last one, or from 0); throws EvaluationError
  // when Newton fails.
  const Vector& solve(const Vector& w);
  const Vector& state() const { return q_; }  // q of the last solve
  int last_newton_iterations() const { return last_iterations_; }
  const ReducedEquilibriumData& data() const { return data_; }
  // New observation targets t and weights c for the same rows B (a new design goal on the same
  // reduced model: the equilibria q(w) do not depend on them and stay warm). Throws
  // std::invalid_argument for sizes other than B's rows or a negative weight.
  void set_observations(Vector target, Vector row_weights);

 private:
  double misfit() const;  // 1/2 sum_i c_i (B q_ - t)_i^2

  ReducedEquilibriumData data_;
  ReducedEquilibriumOptions options_;
  std::shared_ptr<const ReducedDesignModel> model_;
  int r_ = 0;
  Vector q_, w_;
  Matrix stiffness_;  // at (q_, w_)
  bool have_state_ = false;
  int last_iterations_ = 0;
};

}  // namespace tailor
