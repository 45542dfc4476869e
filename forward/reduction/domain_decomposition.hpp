#pragma once
// Domain-decomposed reduced basis in the Craig-Bampton form (Craig & Bampton 1968; Kim &
// James 2011; Yang et al. 2015; docs/reduction.md, "Domain decomposition").
//
// The body's elements are split into domains (domain_partition.hpp). A free DOF is interior to
// domain d when all elements around its vertex belong to d, an interface DOF otherwise; the
// interface DOFs are shared, not duplicated, so any combination of the basis is continuous (the
// interface jump is zero by construction). Per domain, with K_ii, M_ii the interior blocks:
//  - fixed-interface modes: the lowest pairs of K_ii phi = lambda M_ii phi (zero on the interface);
//  - local modal derivatives of its lowest `derivative_modes` fixed-interface modes,
//    -K_ii^{-1} [H(phi_a) phi_b]_i (the order-2 Krylov block with the interface held fixed);
//  - local derivatives of the lowest `boundary_derivative_modes` boundary-driven modes,
//    -K_ii^{-1} [H(psi_a) psi_b]_i: the interior's second-order response to the interface motion
//    (a domain carried through a large rotation by its interface deforms quadratically in it);
//  - interior static responses K_ii^{-1} f_i to given loads.
// Boundary-driven (constraint) modes: for interface excitations u_b (the columns of E),
//   psi = [u_b on the interface;  -K_ii^{-1} K_ib u_b in every domain's interior],
// the static response of the interiors to the interface motion. The excitation rule:
//  - interface_modes = 0: E = I, every interface DOF (then, with the load responses, the basis
//    contains the exact linear static solution: u_i = K_ii^{-1} f_i + Psi u_b);
//  - interface_modes = n: the interface traces of the lowest global vibration modes (K phi =
//    lambda M phi on the whole body) and of the modal derivatives of the lowest k of them
//    (k + k (k + 1) / 2 >= n), in that order, M-orthonormalized, the first n, orthonormalized on
//    the interface: the smooth interface motions the whole body prefers, with their nonlinear
//    (rotational) parts; for a linear material the derivatives vanish and n modes remain. (The
//    interface's own low modes of K_bb e = mu M_bb e are no good: the stiffness that holds an
//    interface vertex dominates its coupling along the interface, so they localize at the
//    vertices with the fewest elements, e.g. corners.)
// With one domain there is no interface and the basis is the global modes and modal
// derivatives (tested). All columns are M-orthonormalized (mass_orthonormal_basis) in the
// order domain 0, ..., domain k-1, boundary-driven; local columns stay local.
//
// Needs a model whose constraints are Dirichlet (a selection elimination) and a body on which
// every K_ii is positive definite. Units: displacement columns, dimensionless after M-normalization.
#include <chrono>
#include <ctime>
#include <string>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

struct DomainDecompositionOptions {
  int fixed_interface_modes = 6;  // per domain (at most its interior DOFs - 1)
  int interface_modes = 0;        // 0 = every interface DOF; n > 0 = n interface modes (see above)
  int derivative_modes = 0;       // per domain: local derivatives of this many lowest fixed-interface modes
  int boundary_derivative_modes = 0;  // per domain: local derivatives of this many lowest boundary-driven modes
  Matrix loads;                   // num_dofs x c force vectors (may be empty): interior static responses
  double step = 0.0;              // finite-difference step of the derivatives; 0 = 1e-3 * extent
  double drop_tolerance = 1e-8;   // mass_orthonormal_basis's
};

// Wall and process CPU seconds (all threads; CPU > wall means parallel work, CPU < wall a
// loaded machine) of the named phases of a precomputation, accumulated over calls of `add`.
struct PhaseTiming {
  std::string name;
  double wall_s = 0.0, cpu_s = 0.0;
};
class PhaseClock {
 public:
  PhaseClock() { restart(); }
  void restart() {
    wall_ = std::chrono::steady_clock::now();
    cpu_ = std::clock();
  }
  // Adds the time since the last add/restart to the phase `name` (appended on first use).
  void add(std::vector<PhaseTiming>& phases, const std::string& name);

 private:
  std::chrono::steady_clock::time_point wall_;
  std::clock_t cpu_;
};

struct DomainDecomposition {
  Matrix basis;                                 // num_dofs x r, basis^T M basis = I
  std::vector<int> column_domain;               // per column: its domain, or -1 (boundary-driven)
  std::vector<std::vector<int>> interior_dofs;  // per domain, full-space DOF indices
  std::vector<int> interface_dofs;              // full-space DOF indices
  int domains = 0;
  int boundary_driven_columns = 0;
  double seconds = 0.0;  // wall time of the whole construction
  std::vector<PhaseTiming> phases;  // where that time went, in order of first use
};

// element_domain: one entry per mesh element in [0, domains). x: the full state (the rest state),
// mass: the full-space mass matrix. Throws std::invalid_argument on bad sizes/options or a
// non-Dirichlet elimination, std::runtime_error when a K_ii is not positive definite or an
// eigen solve fails.
DomainDecomposition domain_decomposition(const Model& model, const Mesh& mesh, const Vector& x, const Vector& p,
                                         const SparseMatrix& mass, const Eigen::VectorXi& element_domain,
                                         const DomainDecompositionOptions& options = {});

// The free unknown of each DOF of a selection elimination (-1 for a held DOF); throws
// std::invalid_argument for any other elimination.
std::vector<int> free_index_of_dofs(const Elimination& elimination);

// Rows of A (square, n x n) and columns picked by index lists, as a sparse |rows| x |cols| matrix.
SparseMatrix sparse_block(const SparseMatrix& A, const std::vector<int>& rows, const std::vector<int>& cols);

}  // namespace tailor
