#pragma once
// Rayleigh damping C = alpha M(rho) + beta K as a dissipation potential (docs/methods.md sections
// 6 and 7):  D(v, p) = alpha/2 v^T M(rho) v + beta/2 v^T K v.
//
// K is the stiffness at the rest state: the Hessian at rest of the small-strain (linear)
// elastic energy with the same per-element Young's modulus and Poisson ratio as the elastic
// term, which every material here (linear, corotated, StVK, Neo-Hookean) shares at rest. As
// the linear energy E_lin is quadratic in the displacement and zero at rest,
// 1/2 v^T K v = E_lin(X + v), so D and all its derivatives in v, alpha, beta, rho, E and nu
// come exactly from ElasticTerm (no third derivatives are needed, and C does not change along
// the trajectory, so the time-dependent adjoint stays exact). Not implemented: K lagged at
// the start of each step (tangent damping), whose dependence on x_n would add third
// derivatives of the elastic energy to the adjoint.
//
// On the hot path (the energy and gradient that Newton and its line search ask for at every
// trial) K is kept as a compressed matrix for the Young's moduli and Poisson ratios it was
// assembled for, so E_lin(X + v) = 1/2 v^T K v and its gradient K v cost one sparse product
// instead of an element loop. Its pattern and the entry each element slot adds to are computed
// once, at construction, so a change of those parameters costs one element loop of Hessian
// values and a scatter, not a triplet assembly. The adjoint's products use it too: the Hessian
// times a vector, (alpha M + beta K) w / kappa, and the K v of the derivatives in alpha and
// beta; the derivatives in E and nu (adjoint only) still run the element loop.
//
// Parameters: alpha = p[alpha_offset] [1/time], beta = p[beta_offset] [time], density through
// the mass operator, Young's modulus and Poisson ratio at the given offsets (per element).
#include <memory>
#include <mutex>

#include "forward/dynamics/damping_term.hpp"
#include "forward/dynamics/mass_operator.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

class RayleighDamping final : public DampingTerm {
 public:
  RayleighDamping(const Mesh& mesh, std::shared_ptr<const MassOperator> mass, int alpha_offset,
                  int beta_offset, int youngs_offset, int poisson_offset);

  std::string name() const override { return "rayleigh_damping"; }
  bool dissipation_is_quadratic() const override { return true; }
  void evaluate_dissipation(const Vector& v, const Vector& p, const EnergyRequest& request) const override;
  void dissipation_pattern(HessianPattern& pattern) const override;
  // (alpha M + beta K) w, with the kept K.
  bool add_dissipation_hessian_times(const Vector& v, const Vector& p, const Vector& w,
                                     Vector& out) const override;
  void add_dissipation_param_gradient(const Vector& v, const Vector& p, Vector& gradient_p) const override;
  void add_dissipation_mixed_transpose_times(const Vector& v, const Vector& p, const Vector& w,
                                             Vector& gradient_p) const override;
  void add_dissipation_mixed(const Vector& v, const Vector& p, Triplets& mixed) const override;

  // The rest stiffness K (for modal analysis and tests).
  SparseMatrix rest_stiffness(const Vector& p) const;

 private:
  // K for the current Young's moduli and Poisson ratios (assembled on first use and when they
  // change; shared so that a caller keeps a consistent matrix while another parameter vector
  // replaces it).
  std::shared_ptr<const SparseMatrix> cached_stiffness(const Vector& p) const;

  std::shared_ptr<const MassOperator> mass_;
  std::unique_ptr<EnergyTerm> stiffness_;  // the linear elastic energy E_lin
  Vector rest_;
  int alpha_offset_, beta_offset_, youngs_offset_, poisson_offset_, num_elements_;
  std::vector<int> slot_entry_;     // per slot of stiffness_'s Hessian pattern: its entry in K
  SparseMatrix stiffness_pattern_;  // K's compressed pattern (values zero)
  mutable std::mutex cache_mutex_;
  mutable Vector cache_key_;  // the Young's moduli, then the Poisson ratios, K was assembled for
  mutable std::shared_ptr<const SparseMatrix> cache_;
  std::size_t mass_slots_, stiffness_slots_;
};

}  // namespace tailor
