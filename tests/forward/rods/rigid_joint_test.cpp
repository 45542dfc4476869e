// The rigid joint's coupling term (forward/rods/rigid_joint_term.hpp): exact gradient and
// Hessian against central differences (check_energy_term) with stale reference frames, a
// non-trivial reference rotation and joint rotation, and a check that can fail. Reference: the
// term's own energy, differentiated numerically.
#include <gtest/gtest.h>

#include "adjoint/derivative_check.hpp"
#include "forward/rigid/rotation.hpp"
#include "forward/rods/rigid_joint_term.hpp"
#include "rod_fixtures.hpp"

namespace tailor::rigid_joint_test {
namespace {

using testing::helix;
using testing::GradientTooStiff;
using testing::uniform_noise;

// Two rods (6 and 5 vertices) meeting at a point, a joint with three members (the first rod's
// last and first edges, the second rod's first edge), its rotation after both rods' DOFs.
struct JointSetup {
  std::shared_ptr<DiscreteRod> a, b;
  std::unique_ptr<RodRigidJointTerm> joint;
  Vector rest;
};

JointSetup make_joint() {
  JointSetup s;
  const Eigen::MatrixX3d pa = helix(6, 1.0, 0.2, 0.4);
  Eigen::MatrixX3d pb = helix(5, 0.7, -0.3, 0.3);
  pb.rowwise() += pa.row(5) - pb.row(0);
  s.a = std::make_shared<DiscreteRod>(pa, 0, 3 * 6);
  s.b = std::make_shared<DiscreteRod>(pb, s.a->dof_end(), s.a->dof_end() + 3 * 5);
  const int offset = s.b->dof_end();
  s.rest = Vector::Zero(offset + 3);
  s.a->write_rest_state(s.rest);
  s.b->write_rest_state(s.rest);
  // A non-trivial reference rotation, and the stress-free state at a non-zero w.
  s.joint = std::make_unique<RodRigidJointTerm>(offset, rigid::rotation_matrix(Eigen::Vector3d(0.3, -0.5, 0.8)));
  s.rest.tail<3>() << 0.4, 0.2, -0.6;
  s.joint->add_member(s.a, 4, Eigen::Vector3d(0.7, 1.3, 2.1), s.rest);
  s.joint->add_member(s.b, 0, Eigen::Vector3d(1.1, 0.9, 1.7), s.rest);
  s.joint->add_member(s.a, 0, Eigen::Vector3d(0.5, 2.0, 0.8), s.rest);
  return s;
}

TEST(RodRigidJoint, StressFreeWhereTheMembersWereAdded) {
  JointSetup s = make_joint();
  EXPECT_LT(s.joint->value(s.rest, Vector()), 1e-28);
  // Rotating the joint by 0.1 rad about the first member's tangent twists that member by
  // sin(0.1) (the joint's copy turns ahead of the edge: psi_0 = -sin 0.1).
  Vector x = s.rest;
  const Eigen::Vector3d t = s.a->edge_vector(s.rest, 4).normalized();
  const Eigen::Matrix3d turned = rigid::rotation_matrix(0.1 * t) * s.joint->joint_frame(s.rest);
  const Eigen::Matrix3d R_ref = s.joint->reference_rotation();
  x.tail<3>() = rigid::rotation_vector(turned * R_ref.transpose(), s.rest.tail<3>());
  const Eigen::Vector3d psi = s.joint->relative_rotation(x, 0);
  EXPECT_NEAR(psi[0], -std::sin(0.1), 1e-14);
  EXPECT_NEAR(psi[1], 0.0, 1e-14);
  EXPECT_NEAR(psi[2], 0.0, 1e-14);
}

TEST(RodRigidJoint, DerivativesWithStaleFramesAndARotatedJointPass) {
  JointSetup s = make_joint();
  const int n = static_cast<int>(s.rest.size());
  const Vector far = s.rest + 0.3 * uniform_noise(n, 3);
  s.a->update_reference_frames(far);
  s.b->update_reference_frames(far);
  const Vector x = s.rest + 0.3 * uniform_noise(n, 4);
  ASSERT_GT(s.joint->value(x, Vector()), 1e-3);
  const EnergyTermCheck c = check_energy_term(*s.joint, x, Vector());
  EXPECT_TRUE(c.passed()) << c.table();
  // w = 0 exactly (the series branch of Rodrigues' coefficients).
  Vector x0 = x;
  x0.tail<3>().setZero();
  const EnergyTermCheck c0 = check_energy_term(*s.joint, x0, Vector());
  EXPECT_TRUE(c0.passed()) << c0.table();
}

TEST(RodRigidJoint, PerturbedDerivativeIsCaught) {
  JointSetup s = make_joint();
  const Vector x = s.rest + 0.3 * uniform_noise(static_cast<int>(s.rest.size()), 5);
  const GradientTooStiff wrong(*s.joint);
  const EnergyTermCheck c = check_energy_term(wrong, x, Vector());
  EXPECT_FALSE(c.checks.front().passed) << c.table();
}

// A rigid joint at an interior vertex replaces the rod's stencil there: an omitted stencil
// contributes nothing (the energy drops by exactly that stencil's share, which the reference
// computes as the difference of two rods' energies) and the derivatives stay exact.
TEST(RodRigidJoint, OmittedStencilLeavesTheEnergyAndStaysExact) {
  testing::RodSetup s = testing::make_rod(helix(7, 1.0, 0.2, 0.6));
  Vector x = s.rest + 0.1 * uniform_noise(s.model->num_dofs(), 6);
  const double bend = s.bending->value(x, s.p), twist = s.twisting->value(x, s.p);
  double shares = 0.0;
  for (int k = 0; k < s.rod->num_interior(); ++k) {
    testing::RodSetup t = testing::make_rod(helix(7, 1.0, 0.2, 0.6));
    t.bending->omit_stencil(k);
    shares += bend - t.bending->value(x, t.p);
  }
  EXPECT_NEAR(shares, bend, 1e-12 * bend);  // the omitted shares add up to the whole energy
  s.bending->omit_stencil(2);
  s.twisting->omit_stencil(2);
  EXPECT_LT(s.bending->value(x, s.p), bend);
  EXPECT_LT(s.twisting->value(x, s.p), twist);
  const EnergyTermCheck cb = check_energy_term(*s.bending, x, s.p);
  EXPECT_TRUE(cb.passed()) << cb.table();
  const EnergyTermCheck ct = check_energy_term(*s.twisting, x, s.p);
  EXPECT_TRUE(ct.passed()) << ct.table();
}

TEST(RodRigidJoint, BadMembersAreRefused) {
  JointSetup s = make_joint();
  EXPECT_THROW(s.joint->add_member(s.a, 5, Eigen::Vector3d::Ones(), s.rest), std::invalid_argument);
  EXPECT_THROW(s.joint->add_member(s.a, 0, Eigen::Vector3d(1, -1, 1), s.rest), std::invalid_argument);
  EXPECT_THROW(RodRigidJointTerm(-1), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::rigid_joint_test
