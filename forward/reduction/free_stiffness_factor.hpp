#pragma once
// The stiffness of a Model in its free unknowns, factorized once, applied to full-space
// right-hand sides: S K_y^{-1} S^T b (x = x0 + S y, see elimination.hpp). Shared by the
// Krylov recurrence and the domain decomposition.
#include <memory>

#include "forward/core/model.hpp"

namespace tailor {

class SparseCholesky;

class FreeStiffnessFactor {
 public:
  // Throws std::runtime_error when K_y(x) is not positive definite (an unconstrained body).
  FreeStiffnessFactor(const Model& model, const Vector& x, const Vector& p);
  ~FreeStiffnessFactor();
  FreeStiffnessFactor(const FreeStiffnessFactor&) = delete;
  FreeStiffnessFactor& operator=(const FreeStiffnessFactor&) = delete;
  Matrix solve(const Matrix& rhs) const;  // full-space columns in, full-space columns out

 private:
  const Model& model_;
  std::unique_ptr<SparseCholesky> factor_;
};

}  // namespace tailor
