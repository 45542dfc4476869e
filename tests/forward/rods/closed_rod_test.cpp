// Closed discrete elastic rods (rings): the closing edge and the wrapped stencils, derivative
// checks with stale frames, the loop's holonomy under large rigid motions, and Michell's
// instability of a twisted ring as validation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "adjoint/derivative_check.hpp"
#include "forward/core/elimination.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/rods/rod_supports.hpp"
#include "rod_fixtures.hpp"

namespace tailor::closed_rod_test {
namespace {

using namespace tailor::testing;

// n vertices on the closed curve (cos phi, sin phi, a sin(2 phi) + b cos(phi)) scaled by R.
// With a != 0 the curve is not planar, and the space-parallel transport around it has a
// non-zero holonomy.
Eigen::MatrixX3d wavy_ring(int n, double R, double a, double b = 0.0) {
  Eigen::MatrixX3d x(n, 3);
  for (int i = 0; i < n; ++i) {
    const double phi = 2.0 * M_PI * i / n;
    x.row(i) << R * std::cos(phi), R * std::sin(phi), R * (a * std::sin(2.0 * phi) + b * std::cos(phi));
  }
  return x;
}

double energy(const RodSetup& s, const Vector& x, const Vector& p) {
  double e = 0.0;
  for (const auto& term : s.model->terms()) e += term->value(x, p);
  return e;
}

Vector perturbed_parameters(const RodSetup& s, unsigned seed) {
  Vector p = s.p;
  const Vector u = uniform_noise(static_cast<int>(p.size()), seed);
  for (int i = 0; i < p.size(); ++i) p[i] = (p[i] == 0.0 ? 0.1 * u[i] : p[i] * (1.0 + 0.2 * u[i]));
  return p;
}

TEST(ClosedRod, LayoutWrapsAroundTheClosingEdge) {
  RodSetup s = make_rod(wavy_ring(6, 1.0, 0.3), {}, Eigen::Vector3d::Zero(), RodTopology::closed);
  const DiscreteRod& rod = *s.rod;
  EXPECT_TRUE(rod.closed());
  EXPECT_EQ(rod.num_edges(), 6);
  EXPECT_EQ(rod.num_interior(), 6);
  EXPECT_EQ(rod.dof_end(), 6 * 3 + 6);
  EXPECT_EQ(rod.edge_end(5), 0);
  EXPECT_EQ(rod.next_edge(5), 0);
  EXPECT_EQ(rod.interior_vertex(5), 0);
  EXPECT_NEAR((rod.edge_vector(s.rest, 5) - (rod.position(s.rest, 0) - rod.position(s.rest, 5))).norm(), 0.0,
              1e-15);
  // Stress-free rest state: zero gradient, including the closing stencil whose stored reference
  // twist is the loop's holonomy (non-zero for this non-planar curve).
  EXPECT_GT(std::abs(rod.stored_reference_twist(5)), 1e-2);
  Vector g = Vector::Zero(s.rest.size());
  for (const auto& term : s.model->terms()) term->add_gradient(s.rest, s.p, g);
  EXPECT_LT(g.lpNorm<Eigen::Infinity>(), 1e-10);
  EXPECT_THROW(clamped_end_dofs(rod, RodEnd::first), std::invalid_argument);
  EXPECT_THROW(
      DiscreteRod(Eigen::MatrixX3d::Random(2, 3), 0, 6, Eigen::Vector3d::Zero(), RodTopology::closed),
      std::invalid_argument);
  // Masses wrap: every vertex of a regular ring gets one edge's mass.
  const Eigen::VectorXd m =
      lumped_vertex_masses(rod, s.material.section, 2.0, Eigen::VectorXd::Ones(6), Eigen::VectorXd::Ones(6));
  EXPECT_NEAR(m.minCoeff(), m.maxCoeff(), 1e-14);
}

// All derivatives of the three terms on a closed, non-planar rod with frames stored at a state
// ~0.3 rad away, random twists and every parameter perturbed: the wrapped stencils (vertices
// n-1, 0, 1 and the closing edge's twist) are exact like the others.
TEST(ClosedRod, DerivativesWithStaleFramesPass) {
  RodMaterial m;
  m.youngs_modulus = 2.0;
  m.shear_modulus = 0.7;
  m.radius = 0.3;
  RodSetup s = make_rod(wavy_ring(7, 1.0, 0.3, 0.2), m, Eigen::Vector3d::Zero(), RodTopology::closed);
  const Vector far = s.rest + 0.3 * uniform_noise(s.model->num_dofs(), 31);
  s.rod->update_reference_frames(far);
  const Vector x = s.rest + 0.3 * uniform_noise(s.model->num_dofs(), 32);
  const Vector p = perturbed_parameters(s, 33);
  DerivativeCheckOptions o;
  o.initial_step = 1e-4;
  for (const auto& term : s.model->terms()) {
    const EnergyTermCheck c = check_energy_term(*term, x, p, o);
    EXPECT_TRUE(c.passed()) << c.table();
  }
}

// The same check catches a closing stencil that is left out of the gradient (a wrapped index
// dropped): the derivative check of such a wrong term must fail.
TEST(ClosedRod, GradientMissingTheClosingStencilIsCaught) {
  RodSetup s = make_rod(wavy_ring(7, 1.0, 0.3, 0.2), {}, Eigen::Vector3d::Zero(), RodTopology::closed);
  const Vector x = s.rest + 0.1 * uniform_noise(s.model->num_dofs(), 34);
  struct Wrong final : EnergyTerm {
    const EnergyTerm& inner;
    const DiscreteRod& rod;
    Wrong(const EnergyTerm& t, const DiscreteRod& r) : inner(t), rod(r) {}
    std::string name() const override { return "wrong"; }
    void evaluate(const Vector& x, const Vector& p, const EnergyRequest& r) const override {
      inner.evaluate(x, p, r);
      if (r.gradient) (*r.gradient)[rod.twist_dof(0)] *= 1.0001;  // 0.01% off on the closing twist
    }
    void hessian_pattern(HessianPattern& pattern) const override { inner.hessian_pattern(pattern); }
  } wrong(*s.twisting, *s.rod);
  const EnergyTermCheck c = check_energy_term(wrong, x, s.p);
  EXPECT_FALSE(c.checks.front().passed) << c.table();
}

// Holonomy: a twisted, bent, non-planar ring moved rigidly (positions and material frames) by 3
// full turns about a tilted axis, in 300 steps with a frame update after each. Its energy (a
// rigid-motion invariant) must not change; it would jump if a reference twist, the closing
// stencil's with the loop's holonomy included, were put on the wrong 2 pi branch.
TEST(ClosedRod, RigidRotationKeepsEnergyWithFrameUpdates) {
  RodSetup s = make_rod(wavy_ring(12, 1.0, 0.4, 0.3), {}, Eigen::Vector3d::Zero(), RodTopology::closed);
  const int n = s.rod->num_vertices();
  Vector x = s.rest;
  for (int j = 0; j < n; ++j) x[s.rod->twist_dof(j)] = 0.7 * std::sin(3.0 * j);  // a twisted state
  x.head(3 * n) += 0.05 * uniform_noise(3 * n, 35);                              // and bent
  const double e0 = energy(s, x, s.p);
  ASSERT_GT(e0, 1e-3);
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.5, 1.0).normalized();
  const int steps = 300;
  const Eigen::Matrix3d step = Eigen::AngleAxisd(3.0 * 2.0 * M_PI / steps, axis).toRotationMatrix();
  double worst = 0.0;
  for (int k = 0; k < steps; ++k) {
    // Rigid motion: positions rotated and each edge's twist set so that its material frame is
    // the rotated old one (the transported reference frame is not the rotated one).
    std::vector<Eigen::Vector3d> m1(static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) m1[static_cast<std::size_t>(j)] = step * s.rod->material_frame(x, j).col(0);
    for (int v = 0; v < n; ++v) x.segment<3>(3 * v) = step * x.segment<3>(3 * v);
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector3d t = s.rod->edge_vector(x, j).normalized(), a1 = s.rod->reference_director(x, j);
      const Eigen::Vector3d& target = m1[static_cast<std::size_t>(j)];
      const double angle = std::atan2(a1.cross(target).dot(t), a1.dot(target));
      double& theta = x[s.rod->twist_dof(j)];
      theta = angle + 2.0 * M_PI * std::round((theta - angle) / (2.0 * M_PI));
    }
    worst = std::max(worst, std::abs(energy(s, x, s.p) - e0) / e0);
    s.rod->update_reference_frames(x);
  }
  EXPECT_LT(worst, 1e-9);
  std::printf("closed ring, 3 rigid turns in 300 steps: largest relative energy change %.2e\n", worst);
}

// ---- Michell's instability ------------------------------------------------------------------
//
// Reference: J. H. Michell, "On the stability of a bent and twisted wire", Messenger of
// Mathematics 19 (1889) 181-184; see A. Goriely, "Twisting and buckling: a review of the
// Michell problem", J. Elasticity 84 (2006) 281-299. A closed ring of radius R made of an
// intrinsically straight rod with isotropic bending stiffness EI and torsional stiffness GJ,
// carrying a uniform twist density tau (total twist Tw = 2 pi R tau), is stable while
//   GJ tau R / EI < sqrt(3),   i.e.   Tw < Tw_c = 2 pi sqrt(3) EI / GJ;
// the instability is the out-of-plane mode of wavenumber 2 (the sqrt(3) is sqrt(n^2 - 1) for
// n = 2). For a circular section, J = 2 I and G = E / (2 (1 + nu)), so GJ / EI = 1 / (1 + nu)
// and Tw_c = 2 pi sqrt(3) (1 + nu); here nu = 0.3 (G = E / 2.6): Tw_c = 14.148 rad.
//
// The imposed twist: the ring's ends were welded after the straight rod was twisted by Tw; for a
// circular section this is a rest twist of -Tw / n at each of the n stencils of the planar ring
// (whose reference twists vanish), i.e. m - mbar = Tw / n in the twisting energy. The planar
// twisted ring (regular polygon, rest lengths = edge lengths, rest curvature 0) is then an
// equilibrium for every Tw, and its stability is the sign of the exact Hessian on a complement
// of its 7 zero modes (3 translations, 3 rotations, a uniform twist). Holding vertex 0 (3 DOFs),
// vertex n/2 in y and z, vertex n/4 in z and theta^0 is such a complement (no rigid motion or
// uniform twist keeps these fixed), and on a complement of the null space H is positive
// semidefinite exactly when the full H is: the critical twist is where the smallest eigenvalue
// of the reduced Hessian changes sign.

struct Ring {
  RodSetup s;
  Vector rest_twist0;  // rest twists of the untwisted ring (zero)
};

Ring michell_ring(int n) {
  const double r = 1e-2;
  RodMaterial m;
  m.radius = r;
  m.youngs_modulus = 4.0 / (M_PI * r * r * r * r);  // EI = 1
  m.shear_modulus = m.youngs_modulus / 2.6;         // nu = 0.3
  Ring ring{make_rod(wavy_ring(n, 1.0, 0.0), m, Eigen::Vector3d::UnitZ(), RodTopology::closed), {}};
  RodSetup& s = ring.s;
  s.p.segment(s.blocks.rest_curvature, 2 * n).setZero();  // intrinsically straight
  ring.rest_twist0 = s.p.segment(s.blocks.rest_twist, n);
  std::vector<int> fixed = pinned_vertex_dofs(*s.rod, 0);
  fixed.push_back(s.rod->position_dof(n / 2, 1));
  fixed.push_back(s.rod->position_dof(n / 2, 2));
  fixed.push_back(s.rod->position_dof(n / 4, 2));
  fixed.push_back(s.rod->twist_dof(0));
  s.model->set_elimination(Elimination::dirichlet(fixed, s.rest));
  return ring;
}

double smallest_ring_eigenvalue(Ring& ring, double twist) {
  RodSetup& s = ring.s;
  const int n = s.rod->num_vertices();
  Vector p = s.p;
  p.segment(s.blocks.rest_twist, n) = ring.rest_twist0.array() - twist / n;
  SparseMatrix H(s.rest.size(), s.rest.size());
  for (const auto& term : s.model->terms()) H += term->hessian(s.rest, p, HessianMode::exact);
  const SparseMatrix& S = s.model->elimination().basis();
  const Matrix reduced = Matrix(S.transpose() * H * S);
  return symmetric_eigenvalues(reduced)[0];
}

double critical_twist(int n) {
  Ring ring = michell_ring(n);
  // The untwisted ring is an equilibrium (zero gradient) with a positive definite reduced Hessian.
  Vector g = Vector::Zero(ring.s.rest.size());
  for (const auto& term : ring.s.model->terms()) term->add_gradient(ring.s.rest, ring.s.p, g);
  EXPECT_LT(g.lpNorm<Eigen::Infinity>(), 1e-8);
  double lo = 8.0, hi = 20.0;  // Tw_c ~ 14.15
  EXPECT_GT(smallest_ring_eigenvalue(ring, lo), 0.0);
  EXPECT_LT(smallest_ring_eigenvalue(ring, hi), 0.0);
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    (smallest_ring_eigenvalue(ring, mid) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(ClosedRodValidation, MichellInstabilityOfTwistedRing) {
  const double michell = 2.0 * M_PI * std::sqrt(3.0) * 1.3;  // EI / GJ = 1 + nu = 1.3
  std::vector<double> errors;
  for (int n : {16, 32, 64}) errors.push_back(std::abs(critical_twist(n) - michell) / michell);
  for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_GT(std::log2(errors[i - 1] / errors[i]), 1.9);
  EXPECT_LT(errors.back(), 1e-2);
  std::printf("Michell ring: relative critical-twist errors at n = 16, 32, 64: %.3e %.3e %.3e\n", errors[0],
              errors[1], errors[2]);
}

}  // namespace
}  // namespace tailor::closed_rod_test
