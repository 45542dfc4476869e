#pragma once
// A bending moment M [force length] about a fixed axis n applied to one edge of a rod, as the
// conservative potential E = -M phi(e), phi the edge's angle about n measured from a fixed
// direction d normal to n: phi = atan2(n . (d x e), d . e) (for an edge in the plane normal to n
// this is its rotation angle; the moment is the planar "follower-free" end couple of the
// elastica). phi is unwrapped to the branch nearest the angle stored at construction or at the
// last update_branch(x), so rotations beyond pi between load steps are tracked.
#include <array>

#include "forward/core/energy_term.hpp"
#include "forward/rods/discrete_rod.hpp"

namespace tailor {

class RodEndMomentTerm final : public EnergyTerm {
 public:
  // Throws std::invalid_argument when axis or direction is zero or they are parallel.
  RodEndMomentTerm(const DiscreteRod& rod, int edge, const Eigen::Vector3d& axis, double moment);
  std::string name() const override { return "rod_end_moment"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  double angle(const Vector& x) const;  // phi [rad], unwrapped
  void update_branch(const Vector& x) { stored_angle_ = angle(x); }
  void set_moment(double moment) { moment_ = moment; }

 private:
  std::array<int, 6> dofs_;
  Eigen::Vector3d axis_, direction_;
  double moment_;
  double stored_angle_ = 0.0;
};

}  // namespace tailor
