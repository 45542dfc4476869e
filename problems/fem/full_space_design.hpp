#pragma once
// The reduced design loop's objective (problems/fem/reduced_design.hpp) with the full-space
// equilibrium in place of the reduced one: what the reduced loop is measured against at equal
// error. Same design w (E = E0 (1 + Y w) over the same material modes), same handle misfit
// 1/2 sum_h W_h |mean u_h - ubar_h|^2 / |ubar_h|^2 (handles free and loaded with their forces),
// same smoothness and positivity terms (design_terms); but every evaluation is a full-space
// Newton solve and its adjoint (StaticFunctional, CHOLMOD), so its cost grows with the mesh.
// Its minimizer is the design the reduced loop approximates.
#include <memory>
#include <vector>

#include "adjoint/static_functional.hpp"
#include "problems/fem/reduced_design.hpp"

namespace tailor {

class FullSpaceDesignFunctional final : public ReducedFunctional {
 public:
  // `design` (its setup, model, material modes and handles) must outlive the functional; its
  // basis and reduced functional are not used.
  explicit FullSpaceDesignFunctional(const ReducedDesign& design);

  int size() const override { return design_.num_design(); }
  double value(const Vector& w) override;
  double value_and_gradient(const Vector& w, Vector& gradient) override;
  const FunctionalCounters& counters() const override { return equilibrium_->counters(); }

  // Per handle, |mean u - ubar| / |ubar| at the last equilibrium solved.
  std::vector<double> handle_errors() const;
  const StaticFunctional& equilibrium() const { return *equilibrium_; }

 private:
  const ReducedDesign& design_;
  ReducedEquilibriumData terms_;  // only the design terms: regularization and positivity
  std::unique_ptr<StaticFunctional> equilibrium_;
};

}  // namespace tailor
