#pragma once
// Twisting moments M_k about the tangents of edges j_k of a rod, as one conservative load:
//   E = -factor sum_k M_k phi_k(x),   phi = theta^j + delta_j(x),
// phi the angle of the edge's material director m1 about the tangent, measured from the rest
// director a1_0 transported to the current tangent along the shortest arc, P(t_0 -> t) a1_0;
// delta_j the signed angle about t from that vector to the reference director a1^j(x) (whose
// transport from the stored frame the rod's terms use). So phi, and the energy, depend on the
// state only, not on where the reference frames were last updated: a load step, a frame
// update and the final residual all see the same function (a force on the twist DOF alone,
// -M theta^j, changes its meaning at every update, because theta is measured from the stored
// frame: the rod_cantilever scene then ended at a load-step dependent tip, reported converged).
//
// The moment this potential represents: its power is M (omega . t - omega_0 . t), omega the
// material frame's angular velocity and omega_0 the spin about t of P(t_0 -> t) a1_0; i.e. the
// moment about the tangent plus, once the edge has turned by an angle alpha from its rest
// direction, a couple of magnitude M tan(alpha / 2) normal to it (the part that makes a moment
// that follows the tangent conservative; docs/rods.md). With the frames at rest (no update),
// delta = 0 and E = -M theta^j.
//
// delta is unwrapped to the branch nearest the value stored at construction (0) or at the last
// update_branches(x), so call that with the frames' update. Valid while no loaded edge turns
// by close to pi from its rest direction (the transport's singularity). Exact gradient and
// Hessian (dual numbers on the edge's 6 position DOFs; theta enters linearly).
#include <memory>
#include <utility>
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/rods/discrete_rod.hpp"

namespace tailor {

class RodTwistingMomentTerm final : public EnergyTerm {
 public:
  // moments: (edge, M) [force length]; several on one edge add up. The rest directions are the
  // rod's stored frames now (construct before any frame update). Throws std::out_of_range for
  // an edge outside the rod.
  RodTwistingMomentTerm(std::shared_ptr<const DiscreteRod> rod, const std::vector<std::pair<int, double>>& moments);
  std::string name() const override { return "rod_twisting_moments"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;

  int num_moments() const { return static_cast<int>(edges_.size()); }
  int edge(int k) const { return edges_[static_cast<std::size_t>(k)]; }
  double moment(int k) const { return moments_[static_cast<std::size_t>(k)]; }
  // phi_k(x) [rad], the loaded edge's material angle from its transported rest director.
  double angle(const Vector& x, int k) const;
  // Stores every delta_k at x as the branch of the next evaluations (after a frame update).
  void update_branches(const Vector& x);
  double factor = 1.0;  // load factor

 private:
  std::shared_ptr<const DiscreteRod> rod_;
  std::vector<int> edges_;
  std::vector<double> moments_;
  std::vector<Eigen::Vector3d> rest_tangents_, rest_directors_;
  std::vector<double> stored_delta_;
};

}  // namespace tailor
