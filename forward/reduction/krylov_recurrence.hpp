#pragma once
// The Krylov block recurrence of the static response to any order k (Yang et al. 2015,
// "Expediting precomputation for reduced deformable simulation", Krylov block subspaces;
// docs/reduction.md, "Krylov recurrence"). Modal derivatives are its order 2.
//
// Let f(u) = dE/dx (x_rest + u) be the internal force and F_m[v_1, ..., v_m] its m-th derivative
// at rest (F_1 = K, F_2[a, b] = H(a) b the stiffness differential, F_3 its directional
// derivative, ...). For start vectors S (linear modes, or static responses K^-1 f), the
// equilibrium under the loads K S q,  f(u(q)) = K S q,  has the Taylor series
//   u(q) = sum_j 1/j! U_j[q, ..., q],   U_1 = S,
// and differentiating j >= 2 times (Faa di Bruno: one term per partition of the j slots) gives
//   U_j(a_1..a_j) = -K^{-1} sum_{partitions pi of {1..j}, |pi| >= 2} F_|pi|[U(a_B) for B in pi]
// with a_B the sub-multiset of the slots in block B. Block P_j holds U_j for every sorted
// multiset a_1 <= ... <= a_j of start columns: C(r + j - 1, j) columns. At j = 2 the only
// partition is two singletons, U_2(a, b) = -K^{-1} H(s_a) s_b: the modal derivatives of
// modal_derivatives.hpp. Higher blocks also need F_3, F_4, ... (non-zero for StVK, whose
// energy is quartic); they are computed by nested central differences of the exact
// Hessian-vector products (exact for StVK up to round-off, O(step^2) otherwise). A basis
// spanning P_1..P_k contains the static response to O(|q|^(k+1)).
//
// Inertia blocks (Yang et al. 2015): K^-1 M P_j, the first term of the Krylov sequence of
// K^-1 M, each column scaled to unit M-norm.
//
// Vectors are full-space displacements, zero on constrained DOFs; K acts on the free unknowns
// of the model's elimination and must be positive definite there (a constrained body).
#include <vector>

#include "forward/core/model.hpp"

namespace tailor {

struct KrylovRecurrenceOptions {
  int order = 2;              // k >= 1: blocks P_1 (= start) .. P_k
  bool inertia_blocks = false;  // also K^-1 M P_j for j = 1..k
  double step = 0.0;          // finite-difference step in length units; 0 = 1e-3 * bounding-box extent
};

struct KrylovRecurrence {
  std::vector<Matrix> blocks;                        // P_1..P_k, num_dofs x C(r + j - 1, j)
  std::vector<std::vector<std::vector<int>>> slots;  // slots[j-1][c]: the sorted multiset of column c
  std::vector<Matrix> inertia;                       // K^-1 M P_j (empty unless asked)
  int force_derivative_evaluations = 0;              // F_m terms evaluated
  // [P_1, ..., P_k, inertia...] side by side (orthonormalize with mass_orthonormal_basis).
  Matrix all() const;
};

// F_m[v_1, ..., v_m] at the full state x [force / length^m times the directions' lengths], m >= 1,
// by nested central differences with steps `step` / max|v_i| for v_2..v_m (m = 1: K v_1 exactly).
Vector force_derivative(const Model& model, const Vector& x, const Vector& p, const std::vector<Vector>& directions,
                        double step);

// The recurrence above at the full state x. Throws std::invalid_argument on bad sizes or
// options, std::runtime_error when K is not positive definite.
KrylovRecurrence krylov_recurrence(const Model& model, const Vector& x, const Vector& p, const SparseMatrix& mass,
                                   const Matrix& start, const KrylovRecurrenceOptions& options = {});

// The non-trivial set partitions of {0..j-1} (every partition but the single block), each as a
// list of blocks of slot indices in increasing order.
std::vector<std::vector<std::vector<int>>> nontrivial_partitions(int j);

}  // namespace tailor
