#pragma once
// The elastic elements of a model seen through a displacement basis u = Phi q: per element e
// (linear simplex), the deformation gradient is affine in q,
//
//   vec F_e(q) = vec I + D_e q,    D_e = d vec(F_e) / dq  (Dim^2 x r),
//
// so its energy V_e Psi(F_e), reduced force V_e D_e^T vec P and reduced stiffness
// V_e D_e^T T D_e (T = d vec P / d vec F) cost O(Dim^2 r^2) whatever the mesh size. This is what a
// cubature rule evaluates (An, Kim, James, "Optimizing cubature for efficient integration of
// subspace deformations", SIGGRAPH Asia 2008, section 3). Any material of an ElasticTerm
// works; it must be linear in Young's modulus at fixed Poisson's ratio (Psi(F; c lambda, c mu) =
// c Psi(F; lambda, mu)), which the constructor checks, so that scaling an element's modulus
// scales its contributions.
#include <memory>
#include <vector>

#include "forward/core/model.hpp"

namespace tailor {

class SubspaceElements {
 public:
  // Every element of every ElasticTerm (2D or 3D) of the model, with the Lame parameters of p;
  // other terms (loads) are ignored. `keep`: only these entries of the full list (indices as
  // element(k) of the full list; empty: all). The model must outlive this object (its
  // materials are referenced). Throws std::invalid_argument for a basis of the wrong height, a
  // model without elastic terms, or a material not linear in Young's modulus.
  SubspaceElements(const Model& model, const Vector& p, const Matrix& basis, const std::vector<int>& keep = {});
  ~SubspaceElements();
  SubspaceElements(SubspaceElements&&) noexcept;
  SubspaceElements& operator=(SubspaceElements&&) noexcept;

  int size() const;          // elements held
  int reduced_size() const;  // r
  int mesh_element(int k) const;
  // Adds scale * (energy, force, stiffness) of element k at q to the requested outputs (which
  // must be sized: 1, r, r x r). Returns false (adding nothing) where the material's values
  // are not finite (e.g. an inverted element of a material with a log barrier).
  bool add(int k, const Vector& q, double scale, double* energy, Vector* force, Matrix* stiffness) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tailor
