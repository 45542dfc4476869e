#pragma once
// Optimized cubature for subspace forces (An, Kim, James, "Optimizing cubature for efficient
// integration of subspace deformations", SIGGRAPH Asia 2008, sections 4-5): choose a few
// elements C and weights omega_e >= 0 so that sum_{e in C} omega_e f_e(q_k) reproduces the
// reduced forces sum_e f_e(q_k) over training poses q_k. Stacked, this is A omega ~ b with
// one column of A per element; the rule minimizes |A_C omega - b| with omega >= 0 (non-negative
// least squares) over a greedily grown C: each step adds the element whose column points most
// along the current residual, then solves the NNLS problem on C and drops the elements whose
// weight vanished (the paper's "greedy cubature", section 5). By default every element is
// scored in every step; with CubatureOptions::candidates, each step scores a random subset of
// that many unchosen elements, as the paper does to keep a step's cost off the mesh size (the
// scores read all of A, rows x elements, every step).
//
// Designs (Xu, Li, Chen, Barbic 2015): with E = E0 (1 + Y w) the force is affine in w, so the
// training matrix stacks, per pose, the base forces f_e and each mode's y_ej f_e: one rule
// that integrates every mode integrates every design w.
#include <vector>

#include "forward/reduction/subspace_elements.hpp"

namespace tailor {

struct CubatureTraining {
  Matrix a;  // rows: poses x (1 + modes) x r, columns: elements
  Vector b;  // the exact sums, A 1
  int poses = 0;
  int skipped_poses = 0;  // where some element could not be evaluated (inverted)
};

// Columns per element: for each pose q_k, each column c of element_weights (indexed by mesh
// element, e.g. [1, y_1, ..., y_m]) the block element_weights(e, c) f_e(q_k). Each pose's
// blocks are scaled by 1 / |b of its first column| so that every pose counts alike (the
// paper's normalization). Throws std::invalid_argument when no pose is usable.
CubatureTraining cubature_training(const SubspaceElements& elements, const std::vector<Vector>& poses,
                                   const Matrix& element_weights);

struct CubatureOptions {
  int max_elements = 120;   // |C| at most
  double tolerance = 1e-3;  // stop at |A omega - b| / |b| <= tolerance
  int candidates = 0;       // elements scored per step (a fresh random subset); 0: every element
  unsigned seed = 1;        // of the candidate subsets (the same seed gives the same rule)
};

struct CubatureRule {
  std::vector<int> elements;  // columns of A (indices into the SubspaceElements)
  Vector weights;             // omega, > 0
  double training_error = 0.0;  // |A_C omega - b| / |b|
  int steps = 0;                // greedy steps
};

// Throws std::invalid_argument for max_elements < 1, tolerance <= 0, candidates < 0 or b = 0.
CubatureRule fit_cubature(const Matrix& a, const Vector& b, const CubatureOptions& options);

}  // namespace tailor
