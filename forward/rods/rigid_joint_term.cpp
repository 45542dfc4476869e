#include "forward/rods/rigid_joint_term.hpp"

#include <stdexcept>
#include <string>

#include "forward/rigid/rotation.hpp"
#include "forward/rods/rod_kinematics.hpp"
#include "forward/rods/rod_stencil_term.hpp"

namespace tailor {

namespace {

constexpr int kJointDofs = 10;  // x_a (0-2), x_b (3-5), theta (6), w (7-9)
using JD = Dual2<kJointDofs>;
using JV = rod_detail::Dual2Vec3<kJointDofs>;
using JointLocal = Eigen::Matrix<double, kJointDofs, 1>;

struct Stored {
  Eigen::Vector3d tangent, director;
};

// psi (twist, about m1, about m2) as dual numbers in the member's 10 DOFs.
std::array<JD, 3> relative_rotation_dual(const JointLocal& local, const Stored& stored,
                                         const Eigen::Matrix3d& reference, const Eigen::Matrix3d& frame) {
  JV xa, xb;
  for (int k = 0; k < 3; ++k) {
    xa[k] = JD::variable(local[k], k);
    xb[k] = JD::variable(local[3 + k], 3 + k);
  }
  const JD theta = JD::variable(local[6], 6);
  const JV e = xb - xa;
  const JV t = reciprocal(rod_detail::norm(e)) * e;
  const JV a1 = rod_detail::transport(JV::constant(stored.tangent), t, JV::constant(stored.director));
  const JV a2 = rod_detail::cross(t, a1);
  const JD c = cos(theta), s = sin(theta);
  const std::array<JV, 3> d = {t, c * a1 + s * a2, c * a2 - s * a1};

  // The joint's copy D_k = R(w) R_ref u_k, with R's exact first and second derivatives in w.
  const Eigen::Vector3d w(local[7], local[8], local[9]);
  const rigid::RotationDerivatives R = rigid::rotation_derivatives(w);
  std::array<JV, 3> D;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d u = reference * frame.col(k);
    const Eigen::Vector3d value = R.rotation * u;
    for (int i = 0; i < 3; ++i) {
      JD& Di = D[static_cast<std::size_t>(k)][i];
      Di = JD(value[i]);
      for (int l = 0; l < 3; ++l) {
        Di.g[7 + l] = (R.first[static_cast<std::size_t>(l)] * u)[i];
        for (int m = 0; m < 3; ++m)
          Di.h(7 + l, 7 + m) = (R.second[static_cast<std::size_t>(l)][static_cast<std::size_t>(m)] * u)[i];
      }
    }
  }
  using rod_detail::dot;
  return {0.5 * (dot(D[2], d[1]) - dot(D[1], d[2])), 0.5 * (dot(D[0], d[2]) - dot(D[2], d[0])),
          0.5 * (dot(D[1], d[0]) - dot(D[0], d[1]))};
}

}  // namespace

Eigen::Vector3d rigid_joint_stiffness(const CrossSection& section, double youngs_modulus,
                                      double shear_modulus, double radius, double rest_length) {
  if (!(rest_length > 0.0))
    throw std::invalid_argument("rigid_joint_stiffness: rest length must be positive");
  const double r4 = radius * radius * radius * radius;
  return Eigen::Vector3d(2.0 * shear_modulus * section.torsion_coefficient() * r4,
                         2.0 * youngs_modulus * section.bending_coefficient2() * r4,
                         2.0 * youngs_modulus * section.bending_coefficient1() * r4) /
         rest_length;
}

RodRigidJointTerm::RodRigidJointTerm(int rotation_offset, const Eigen::Matrix3d& reference_rotation)
    : rotation_offset_(rotation_offset), reference_(reference_rotation) {
  if (rotation_offset < 0) throw std::invalid_argument("RodRigidJointTerm: negative rotation offset");
}

Eigen::Matrix3d RodRigidJointTerm::joint_frame(const Vector& x) const {
  return rigid::rotation_matrix(x.segment<3>(rotation_offset_)) * reference_;
}

void RodRigidJointTerm::add_member(std::shared_ptr<const DiscreteRod> rod, int edge,
                                   const Eigen::Vector3d& stiffness, const Vector& x) {
  if (!rod) throw std::invalid_argument("RodRigidJointTerm: no rod given");
  if (edge < 0 || edge >= rod->num_edges())
    throw std::invalid_argument("RodRigidJointTerm: edge " + std::to_string(edge) + " out of range");
  if (!(stiffness.minCoeff() >= 0.0) || !stiffness.allFinite())
    throw std::invalid_argument("RodRigidJointTerm: stiffness must be finite and non-negative");
  if (x.size() < std::max(rod->dof_end(), rotation_offset_ + 3))
    throw std::invalid_argument("RodRigidJointTerm: state too short for the member or the joint");
  Member m;
  m.rod = rod;
  m.edge = edge;
  m.stiffness = stiffness;
  Eigen::Matrix3d d;
  d.col(0) = rod->edge_vector(x, edge).normalized();
  d.rightCols<2>() = rod->material_frame(x, edge);
  m.frame = joint_frame(x).transpose() * d;
  for (int k = 0; k < 3; ++k) {
    m.dofs[static_cast<std::size_t>(k)] = rod->position_dof(edge, k);
    m.dofs[static_cast<std::size_t>(3 + k)] = rod->position_dof(rod->edge_end(edge), k);
    m.dofs[static_cast<std::size_t>(7 + k)] = rotation_offset_ + k;
  }
  m.dofs[6] = rod->twist_dof(edge);
  members_.push_back(std::move(m));
}

Eigen::Vector3d RodRigidJointTerm::relative_rotation(const Vector& x, int member) const {
  const Member& m = members_.at(static_cast<std::size_t>(member));
  JointLocal local;
  for (int r = 0; r < kJointDofs; ++r) local[r] = x[m.dofs[static_cast<std::size_t>(r)]];
  const auto psi = relative_rotation_dual(
      local, {m.rod->stored_tangent(m.edge), m.rod->stored_director(m.edge)}, reference_, m.frame);
  return {psi[0].v, psi[1].v, psi[2].v};
}

void RodRigidJointTerm::evaluate(const Vector& x, const Vector&, const EnergyRequest& request) const {
  double energy = 0.0;
  for (std::size_t k = 0; k < members_.size(); ++k) {
    const Member& m = members_[k];
    JointLocal local;
    for (int r = 0; r < kJointDofs; ++r) local[r] = x[m.dofs[static_cast<std::size_t>(r)]];
    const auto psi = relative_rotation_dual(
        local, {m.rod->stored_tangent(m.edge), m.rod->stored_director(m.edge)}, reference_, m.frame);
    JointLocal g = JointLocal::Zero();
    Eigen::Matrix<double, kJointDofs, kJointDofs> H = Eigen::Matrix<double, kJointDofs, kJointDofs>::Zero();
    for (int a = 0; a < 3; ++a) {
      const double K = m.stiffness[a];
      const JD& s = psi[static_cast<std::size_t>(a)];
      energy += 0.5 * K * s.v * s.v;
      g += K * s.v * s.g;
      H += K * (s.g * s.g.transpose() + s.v * s.h);
    }
    if (request.gradient)
      for (int r = 0; r < kJointDofs; ++r) (*request.gradient)[m.dofs[static_cast<std::size_t>(r)]] += g[r];
    if (request.hessian_values) {
      H = 0.5 * (H + H.transpose()).eval();
      if (request.hessian_mode == HessianMode::projected) project_psd(H);
      std::copy(H.data(), H.data() + kJointDofs * kJointDofs,
                request.hessian_values + k * kJointDofs * kJointDofs);
    }
  }
  if (request.value) *request.value += energy;
}

void RodRigidJointTerm::hessian_pattern(HessianPattern& pattern) const {
  for (const Member& m : members_)
    for (int c = 0; c < kJointDofs; ++c)
      for (int r = 0; r < kJointDofs; ++r)
        pattern.push_back({m.dofs[static_cast<std::size_t>(r)], m.dofs[static_cast<std::size_t>(c)]});
}

}  // namespace tailor
