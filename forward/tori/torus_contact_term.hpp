#pragma once
// TorusContactTerm: the IPC barrier on the implicit distance between tori (docs/tori.md), an
// EnergyTerm over the rigid DOFs of forward/rigid (torus i owns q[6i .. 6i+5] = (T_i, w_i)):
//   B(q, p) = kappa sum_{pairs} b(d_ab^2, d_hat^2),
// b the barrier of forward/contact/barrier.hpp on squared distances, d_ab the torus distance
// (torus_distance.hpp) with exact first and second derivatives by the implicit function theorem,
// summed over the pairs whose bounding spheres (radius R + max(r, r1) about T) come within d_hat.
//
// Parameters: with parameter_offset >= 0 torus i's radii are p[offset + 2i] (R) and
// p[offset + 2i + 1] (r), with the derivatives add_param_gradient / add_mixed; otherwise the
// shapes given at construction (p is not read). An elliptic torus keeps its r1 (not a parameter).
// With placement_offset >= 0 the pose of the k-th fixed torus (in body order) is its placement
// p[offset + 6k .. offset + 6k + 5] = (T, w) instead of its entries of q: the equilibrium of the
// free tori then depends on where the anchors are, through the barrier between an anchor and the
// links touching it. The derivatives in a placement are the anchor's 6 rows and columns of the
// pair's 16 x 16 Hessian (torus_distance.hpp), which no DOF owns: add_param_gradient gets the
// anchor's part of the pair gradient, add_mixed the free torus's rows of the anchor's columns.
// Such a torus's entries of q are not read (its gradient and Hessian rows there are zero).
//
// Hessian pattern: a dense 12 x 12 block for each candidate pair (all pairs, or |i - j| <= band
// for chains). A pair that is not a candidate coming within d_hat throws std::runtime_error
// (its coupling is not in the solver's pattern); max_step() guards all pairs regardless.
//
// max_step(): conservative advancement on the implicit distance along the curved rigid paths
// q + t dq, t in [0, 1]: d_ab(t) is Lipschitz with L = |dT_a| + |dw_a| R_a + |dT_b| + |dw_b| R_b
// (a core point moves no faster; the rotation's left Jacobian has norm <= 1; for a pair with an
// elliptic torus, whose distance is between surface points, R + max(r, r1) for R), so from a time t
// with distance d(t) the path keeps d >= (1 - ccd_fraction) d(0) > 0 until t + (d(t) - (1 -
// ccd_fraction) d(0)) / L; the distance is re-measured there, and so on up to t = 1. The step
// returned is certified (no tunnelling, no tangent miss) as long as the distance query finds
// the global minimum of the core distance. It uses the shapes given at construction and every
// torus's pose in q (no p): with placements from p the caller keeps a fixed torus's q entries at
// its placement (a placement perturbed in p alone is not seen by the step bound; the barrier's
// infinite value on overlap, evaluated at p, still rejects a crossing step in the line search).
#include <vector>

#include "forward/contact/barrier.hpp"
#include "forward/core/energy_term.hpp"
#include "forward/rigid/rigid_body_system.hpp"
#include "forward/tori/torus_distance.hpp"

namespace tailor::tori {

// One pair's barrier kappa b(d^2, d_hat^2) (forward/contact/barrier.hpp) with its first and
// second derivatives in the distance d (chain rule through s = d^2); infinite for d <= 0.
contact::ScalarDerivatives pair_barrier(double d, double d_hat, double kappa);

struct TorusContactOptions {
  double activation_distance = 1e-2;  // d_hat [length]
  double stiffness = 1.0;             // kappa [energy / length^4]
  int pair_band = 0;                  // 0: every pair is a candidate; k > 0: pairs with |i - j| <= k
  int parameter_offset = -1;          // >= 0: radii read from p (see above)
  int placement_offset = -1;          // >= 0: the fixed tori's poses read from p (see above)
  double ccd_fraction = 0.9;          // share of a pair's gap one step may close
  DistanceOptions distance;
};

// The contact force of one pair: -dB/dT_b on torus b (a gets the opposite) [force].
struct TorusPairForce {
  int a = 0, b = 0;
  double distance = 0.0;
  Eigen::Vector3d force_on_b = Eigen::Vector3d::Zero();
};

struct TorusPair {
  int a = 0, b = 0;
  TorusDistance distance;
};

class TorusContactTerm final : public EnergyTerm {
 public:
  // One shape per body of `system` (which must outlive the term). Throws std::invalid_argument
  // on a count mismatch, a bad shape, or non-positive d_hat / kappa.
  TorusContactTerm(const rigid::RigidBodySystem& system, std::vector<TorusShape> shapes,
                   TorusContactOptions options);

  std::string name() const override { return "torus_contact"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override;
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override;
  double max_step(const Vector& x, const Vector& dx) const override;

  int num_tori() const { return static_cast<int>(shapes_.size()); }
  const TorusContactOptions& options() const { return options_; }
  void set_stiffness(double kappa) { options_.stiffness = kappa; }
  TorusShape shape(int i, const Vector& p) const;
  TorusPose pose(int i, const Vector& q, const Vector& p) const;
  bool is_candidate(int a, int b) const;
  // The first of a candidate pair's 144 Hessian slots (12 x 12, a's DOFs first), -1 for a pair
  // that is not a candidate; num_slots() in all (terms on the same pairs share this layout).
  int pair_slot(int a, int b) const;
  int num_slots() const { return num_slots_; }
  // The number of fixed tori (6 placement parameters each with placement_offset >= 0).
  int num_placements() const { return num_placements_; }
  // Whether torus i's pose is read from p (a fixed torus with placement_offset >= 0).
  bool placed_by_parameters(int i) const {
    return options_.placement_offset >= 0 && placement_index_[static_cast<std::size_t>(i)] >= 0;
  }
  // The pairs whose bounding spheres come within `range`, with their distances.
  std::vector<TorusPair> close_pairs(const Vector& q, const Vector& p, double range, bool derivatives) const;
  // Smallest distance over the pairs within `range` (infinity if none).
  double min_distance(const Vector& q, const Vector& p, double range) const;
  // The active pairs' forces at q.
  std::vector<TorusPairForce> pair_forces(const Vector& q, const Vector& p) const;
  // Pairs with d < d_hat at q.
  int active_pairs(const Vector& q, const Vector& p) const;

  // Conservative advancement of one pair along dq (bodies a and b, 6 DOFs each in q; shapes sa,
  // sb): the largest t <= alpha to which their distance provably stays above (1 - ccd_fraction)
  // times its start, from the pair's speed bound; alpha when their bounding spheres cannot meet,
  // 0 when they touch at the start. max_step() is its minimum over the pairs.
  double pair_max_step(int a, int b, const TorusShape& sa, const TorusShape& sb, const Vector& q, const Vector& dq,
                       double alpha) const;

  // Work counters of max_step: calls and distance queries.
  mutable long ccd_calls = 0, ccd_queries = 0;

 private:
  int placement_column(int i) const;  // first placement parameter of torus i, -1 when not placed by p

  const rigid::RigidBodySystem& system_;
  std::vector<TorusShape> shapes_;
  TorusContactOptions options_;
  std::vector<int> pair_slot_;  // n x n: first Hessian slot of a candidate pair, -1 otherwise
  int num_slots_ = 0;
  std::vector<int> placement_index_;  // per torus: k for the k-th fixed one, -1 when free
  int num_placements_ = 0;
};

}  // namespace tailor::tori
