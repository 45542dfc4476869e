#pragma once
// Reduced model of any material by projection: W(q) = E(x0 + Phi q) over every term of a
// Model, force Phi^T dE/dx, stiffness Phi^T (d2E/dx2) Phi from one assembly of the exact
// Hessian per term. Every evaluation visits the whole mesh: the cost is O(mesh size * r) for
// the force and O(mesh size * r^2) for the stiffness, unlike ReducedStvk. Kept as the
// reference and for materials without polynomial structure.
#include "forward/core/model.hpp"
#include "forward/reduction/reduced_elastic_model.hpp"

namespace tailor {

class ProjectedReducedModel final : public ReducedElasticModel {
 public:
  // model and p are referenced / copied; x0: the full state at q = 0 (usually the rest state);
  // basis: num_dofs x r displacement basis. Throws std::invalid_argument on size mismatch.
  ProjectedReducedModel(const Model& model, Vector p, Vector x0, Matrix basis);
  int size() const override { return static_cast<int>(basis_.cols()); }
  void evaluate(const Vector& q, double* energy, Vector* force, Matrix* stiffness) const override;

 private:
  const Model& model_;
  Vector p_, x0_;
  Matrix basis_;
};

}  // namespace tailor
