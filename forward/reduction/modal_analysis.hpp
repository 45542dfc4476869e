#pragma once
// Modal analysis of a Model (docs/methods.md section 7): the lowest
// eigenpairs of
//
//   K phi = lambda M phi,   K = S^T (d2E/dx2)(x) S,  M = S^T M_full S,
//
// in the free unknowns of the model's constraints (Dirichlet DOFs eliminated), solved by
// ARPACK shift-invert on a CHOLMOD factor of K - sigma M (generalized_eigen.hpp). lambda =
// omega^2 [1/s^2 in consistent units], frequency = sqrt(lambda) / (2 pi) [Hz].
//
// Free-floating bodies. K is singular on the rigid motions the constraints admit (6 in 3D, 3
// in 2D for a free body; fewer for a pinned one). They are built explicitly
// (admissible_rigid_modes), checked to be null modes of K (|K r| <= rigid_tolerance * max K_ii
// * |r|; a pre-stressed state fails this and is reported) and set apart:
//  - RigidModeHandling::deflate: projected out of every Lanczos vector (the default);
//  - RigidModeHandling::shift: not projected; the negative default shift keeps K - sigma M
//    positive definite, count + k pairs are computed, and the k eigenvectors lying in the
//    rigid subspace are identified and set apart (an error if they are not exactly k).
// Both give the same elastic modes (tested).
#include <string>

#include "forward/core/model.hpp"
#include "forward/reduction/generalized_eigen.hpp"

namespace tailor {

enum class RigidModeHandling { deflate, shift };

struct ModalAnalysisOptions {
  int count = 10;  // elastic modes wanted
  RigidModeHandling rigid = RigidModeHandling::deflate;
  double rigid_tolerance = 1e-8;  // relative null-mode residual of a rigid motion (see above)
  GeneralizedEigenOptions eigen;  // passed on (its deflation is set here)
};

struct ModalAnalysis {
  Matrix modes;              // num_dofs x count, full DOF space (0 on constrained DOFs); modes^T M modes = I
  Vector eigenvalues;        // count, ascending, lambda = omega^2
  Vector frequencies;        // count, Hz: sqrt(lambda) / (2 pi)
  Matrix rigid_modes;        // num_dofs x k, M-orthonormal rigid-body modes (k = 0 for a clamped body)
  Vector rigid_eigenvalues;  // k, their Rayleigh quotients r^T K r (round-off)
  Matrix free_modes;         // num_free x count: the same modes in the free unknowns y
  GeneralizedEigenResult solve;  // diagnostics (eigenvectors moved out)
};

// Modes of the model (DOFs interleaved in dimension dim = 2 or 3) at the full state x (the
// rest state for modal analysis at rest) with parameters p and full-space mass matrix `mass`
// (forward/fem/mass.hpp). Throws std::invalid_argument for bad sizes or count, std::runtime_error when the
// eigen solve fails or a rigid motion is not a null mode of K (message included).
ModalAnalysis modal_analysis(const Model& model, int dim, const Vector& x, const Vector& p,
                             const SparseMatrix& mass, const ModalAnalysisOptions& options = {});

// sqrt(max(lambda, 0)) / (2 pi) entrywise.
Vector frequencies_hz(const Vector& eigenvalues);

}  // namespace tailor
