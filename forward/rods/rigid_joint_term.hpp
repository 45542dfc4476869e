#pragma once
// Rigid joint of a rod network (docs/rods.md, "Rigid joints"): a joint carries a rotation
// vector w (three DOFs at x[rotation_offset + k]) about a stored reference rotation R_ref, so
// its frame is Q(w) = R(w) R_ref (Rodrigues, forward/rigid/rotation.hpp, exact derivatives).
// Each member edge j at the joint keeps the material frame (d_0, d_1, d_2) = (t, m1, m2) it had
// at the joint's stress-free state, stored in the joint's frame as u_k (so the joint's copy is
// D_k = R(w) R_ref u_k). The coupling is elastic (a stiff ghost stencil, not an exact
// constraint): with the relative rotation's components in the joint's copy of the frame
//   psi_0 = (D_2 . d_1 - D_1 . d_2) / 2   (about the tangent: twist),
//   psi_1 = (D_0 . d_2 - D_2 . d_0) / 2   (about m1),
//   psi_2 = (D_1 . d_0 - D_0 . d_1) / 2   (about m2),
// (psi = sin(phi) n for a relative rotation by phi about n, in the joint's frame)
//   E = sum_members 1/2 (K_0 psi_0^2 + K_1 psi_1^2 + K_2 psi_2^2).
// rigid_joint_stiffness gives K = (2 GJ, 2 E I2, 2 E I1) / L_j: the bending and twisting
// stencil of docs/rods.md whose other edge has zero length (lbar = L_j), so two members in
// series have the compliance of an interior vertex of one rod turning the corner.
// Per member the DOFs are the edge's two vertices (0-5), its twist (6) and w (7-9); the
// material frame uses the rod's stored reference frame (time-parallel transport), and the
// gradient and Hessian are exact at any x for the stored frames (dual numbers). The stiffnesses
// are fixed numbers, not parameters (a designed radius does not change them).
#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/rods/cross_section.hpp"
#include "forward/rods/discrete_rod.hpp"

namespace tailor {

// (K_twist, K_about_m1, K_about_m2) = (2 G J, 2 E I2, 2 E I1) / rest_length for a section of size r.
Eigen::Vector3d rigid_joint_stiffness(const CrossSection& section, double youngs_modulus, double shear_modulus,
                                      double radius, double rest_length);

class RodRigidJointTerm final : public EnergyTerm {
 public:
  // Throws std::invalid_argument for a negative offset.
  explicit RodRigidJointTerm(int rotation_offset,
                             const Eigen::Matrix3d& reference_rotation = Eigen::Matrix3d::Identity());
  std::string name() const override { return "rod_rigid_joint"; }

  // Adds edge `edge` of `rod` as a member, stress-free at state x (its material frame at x is
  // stored in the joint's frame Q(w(x))). Throws std::invalid_argument for a bad edge or a
  // negative stiffness.
  void add_member(std::shared_ptr<const DiscreteRod> rod, int edge, const Eigen::Vector3d& stiffness,
                  const Vector& x);
  int num_members() const { return static_cast<int>(members_.size()); }
  int rotation_offset() const { return rotation_offset_; }
  const Eigen::Matrix3d& reference_rotation() const { return reference_; }
  // Moves the reference rotation to Q(w(x)) (after which w = 0 describes the same frame): a
  // driver that calls it must also set the joint's DOFs of its state to zero.
  void set_reference_rotation(const Eigen::Matrix3d& reference) { reference_ = reference; }
  // The joint frame Q(w) = R(w) R_ref at x.
  Eigen::Matrix3d joint_frame(const Vector& x) const;
  // psi (twist, about m1, about m2) of member k at x [rad, sin of the relative angle].
  Eigen::Vector3d relative_rotation(const Vector& x, int member) const;

  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;

 private:
  struct Member {
    std::shared_ptr<const DiscreteRod> rod;
    int edge;
    Eigen::Vector3d stiffness;
    Eigen::Matrix3d frame;  // columns u_0, u_1, u_2 (t, m1, m2 at the stress-free state, joint frame)
    std::array<int, 10> dofs;
  };
  int rotation_offset_;
  Eigen::Matrix3d reference_;
  std::vector<Member> members_;
};

}  // namespace tailor
