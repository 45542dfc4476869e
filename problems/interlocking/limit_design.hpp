#pragma once
// Inverse design of deformation limits (docs/interlocking.md, "Designing limits"): design
// variables z are selected master radii (R_i or r_i) and the lattice scale is kept, and
//   T(z) = sum_k 1/2 (s*_k(z) - target_k)^2,
// s*_k the lock-up strain along load path k (forward/interlocking/strain_boundary.hpp) with the
// exact gradient ds*_k/dz of limit_sensitivity.hpp (implicit function theorem on the lock-up
// state, one adjoint solve per path). Each evaluation continues every path's last lock-up state
// by the augmented Newton (the same branch as z moves); a path whose continuation fails is swept
// afresh. Non-penetration margins: the rest placement's pair distances d_ab(z) >= margin for the
// pairs within reach at the start (margin_constraints), so that every design can be built.
// Bending patches (RigidCellSpec::bending_patch) are designed the same way: the targets are
// curvature limits, and a variable's `element` names an element of the tiling the patch was cut
// from (CellElement::origin), so that it sets the radius of every copy (the gradient sums them).
#include <memory>
#include <string>
#include <vector>

#include "adjoint/reduced_functional.hpp"
#include "forward/interlocking/limit_sensitivity.hpp"
#include "optimizers/optimizer.hpp"

namespace tailor {

struct LimitTarget {
  interlocking::LoadPath path;
  double strain = 0.0;  // the target limit s_t
};

struct DesignVariable {
  int element = 0;    // a master, or for a patch cut from a tiling the tiling's element
  bool major = true;  // R (true) or r
  double lower = 0.0, upper = 0.0;
};

// The entries of master_radii(spec) a variable sets: R or r of every element whose origin (its
// own index when it has none) is `element`. Throws std::invalid_argument when there is none.
std::vector<int> radius_entries(const interlocking::RigidCellSpec& spec, const DesignVariable& variable);

class LimitDesignFunctional final : public ReducedFunctional {
 public:
  LimitDesignFunctional(interlocking::RigidCellSpec base, std::vector<DesignVariable> variables,
                        std::vector<LimitTarget> targets, interlocking::LimitOptions options);

  int size() const override { return static_cast<int>(variables_.size()); }
  double value(const Vector& z) override;
  double value_and_gradient(const Vector& z, Vector& gradient) override;

  Vector initial_design() const;
  interlocking::RigidCellSpec spec_at(const Vector& z) const;
  // The limits s*_k at the last evaluated z.
  const std::vector<double>& limits() const { return limits_; }
  Bounds bounds() const;
  // margin - d_ab(z) <= 0 for the pairs within `reach` of each other at the initial design.
  std::vector<Constraint> margin_constraints(double margin, double reach) const;

 private:
  double evaluate(const Vector& z, Vector* gradient);
  interlocking::RigidCellSpec base_;
  std::vector<DesignVariable> variables_;
  std::vector<std::vector<int>> entries_;  // radius_entries of each variable
  std::vector<LimitTarget> targets_;
  interlocking::LimitOptions options_;
  struct PathState {
    bool valid = false;
    Vector y;
    double strain = 0.0;
    int a = -1, b = -1;
  };
  std::vector<PathState> states_;
  std::vector<double> limits_;
};

}  // namespace tailor
