// Periodic rigid cells of interlocking tori: the images follow their masters, F = I is force-free,
// a straight chain locks at its closed-form stretch, no reported state interpenetrates, and the
// broad phase gives the all-pairs results.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>
#include <vector>

#include "forward/interlocking/cell_patterns.hpp"
#include "forward/interlocking/interpenetration_check.hpp"
#include "forward/interlocking/strain_boundary.hpp"

namespace tailor::interlocking::periodic_cell_test {
namespace {

const tori::TorusShape kRing{1.0, 0.2};

TEST(PeriodicRigidCell, ImagesFollowTheirMastersUnderTheMacroDeformation) {
  const PeriodicRigidCell cell(square_ring_cell(kRing, kRing, kRing, 1.5));
  ASSERT_EQ(cell.num_elements(), 3);
  EXPECT_EQ(cell.num_free(), 6 * 3 - 3);
  EXPECT_EQ(cell.num_bodies(), 3 * 5);  // four half-lattice shifts with one ring
  Eigen::Matrix2d F;
  F << 1.1, 0.05, -0.02, 0.9;
  Vector y = cell.rest_free_state();
  y += 0.01 * Vector::LinSpaced(y.size(), -1.0, 1.0);
  const Vector x = cell.full_state(y, F);
  const Vector q = cell.master_state(y);
  for (int body = 0; body < cell.num_bodies(); ++body) {
    const int i = cell.master(body);
    const Eigen::Vector2d t = F * cell.spec().lattice * cell.shift(body).cast<double>();
    EXPECT_LT((x.segment<3>(6 * body) - q.segment<3>(6 * i) - Eigen::Vector3d(t.x(), t.y(), 0)).norm(), 1e-14);
    EXPECT_EQ(x.segment<3>(6 * body + 3), q.segment<3>(6 * i + 3));
  }
  // The anchor's translation is held.
  EXPECT_EQ(q.segment<3>(0), Eigen::Vector3d::Zero());
  // The Elimination object is the same map.
  EXPECT_LT((cell.elimination(F).expand(y) - x).norm(), 1e-14);
}

// F = I: the rest placement is an equilibrium with zero force on every master and zero macro
// reaction; a chain pulled until its rings press has a macro reaction (the check can fail).
TEST(PeriodicRigidCell, IdentityMacroDeformationGivesZeroForce) {
  RigidCellSpec spec = square_ring_cell(kRing, kRing, kRing, 1.5);
  spec.activation_distance = 0.05;  // wide, so that a compressed cell is surely within reach
  const PeriodicRigidCell cell(spec);
  const Vector x = cell.full_state(cell.rest_free_state(), Eigen::Matrix2d::Identity());
  const ReducedContact c = reduced_contact(cell, x, false);
  EXPECT_EQ(c.gradient.norm(), 0.0);
  for (int k = 0; k < 2; ++k)
    for (int l = 0; l < 2; ++l) EXPECT_EQ(c.full_gradient.dot(cell.state_derivative_macro(k, l)), 0.0);
  // A chain pulled to its lock: the images press the masters.
  const RigidCellSpec chain = chain_cell(kRing, kRing, 1.5, 10.0);
  const PeriodicRigidCell pulled(chain);
  Eigen::Matrix2d F = Eigen::Matrix2d::Identity();
  F(0, 0) = (2.0 * (1.0 - 0.2) - 0.3 * pulled.activation_distance()) / 1.5;
  Vector y = pulled.rest_free_state();
  y[3] = F(0, 0) * 1.5;  // the link's x (y: the node's w, then the link's T and w)
  const ReducedContact p = reduced_contact(pulled, pulled.full_state(y, F), false);
  // The link sits between two nodes pulling equally (zero net force on the masters), but the
  // macro reaction dB/dF_xx is not zero.
  EXPECT_GT(p.full_gradient.dot(pulled.state_derivative_macro(0, 0)), 0.1);
}

// Reference (closed form, two perpendicular rings pulled apart touch at their inner equators):
// the centre spacing at lock is 2(R - r) - lock_fraction d_hat, so the stretch limit of a chain
// with rest spacing s0 is (2(R - r) - d_hat / 2) / s0 - 1 (-> 2(R - r)/s0 - 1 as d_hat -> 0).
TEST(PeriodicRigidCell, StraightChainLocksAtTheClosedFormStretch) {
  for (const auto& [R, r, s0] : {std::array<double, 3>{1.0, 0.2, 1.5}, std::array<double, 3>{1.0, 0.3, 1.35}}) {
    const tori::TorusShape ring{R, r};
    const PeriodicRigidCell cell(chain_cell(ring, ring, s0, 10.0));
    LimitOptions options;
    options.max_strain = 0.5;
    const Vector y_rest = rest_equilibrium(cell);
    const LimitPoint p = find_limit(cell, uniaxial_path(0.0), y_rest, options);
    ASSERT_TRUE(p.locked) << p.status;
    EXPECT_TRUE(p.refined);
    const double expected = (2.0 * (R - r) - 0.5 * cell.activation_distance()) / s0 - 1.0;
    std::printf("chain R=%g r=%g s0=%g: limit %.12f, closed form %.12f (geometric %.6f), %d solves\n", R, r, s0,
                p.strain, expected, 2.0 * (R - r) / s0 - 1.0, p.solves);
    EXPECT_NEAR(p.strain, expected, 1e-8);
    EXPECT_NEAR(p.min_distance, 0.5 * cell.activation_distance(), 1e-12);
    // Two pair classes press (node - link and link - next node), each carrying the same force.
    ASSERT_EQ(p.active.size(), 2u);
    EXPECT_NEAR(p.active[0].force_on_b.norm(), p.active[1].force_on_b.norm(), 1e-6);
    // Independent check: certified core-circle bounds, and the contact model's distance inside them.
    const ClearanceReport clearance = check_clearance(cell, cell.full_state(p.y, p.deformation));
    EXPECT_TRUE(clearance.apart());
    for (const PairClearance& c : clearance.pairs)
      if (c.upper < cell.activation_distance()) {
        EXPECT_LE(c.lower, p.min_distance + 1e-12);
        EXPECT_GE(c.upper, p.min_distance - 1e-12);
      }
    // Sideways (no neighbours along y) it never locks.
    const LimitPoint side = find_limit(cell, uniaxial_path(0.5 * M_PI), y_rest, options);
    EXPECT_FALSE(side.locked);
  }
}

// The independent check sees an overlap: two perpendicular rings pushed through each other's tube.
TEST(PeriodicRigidCell, ClearanceCheckSeesInterpenetration) {
  double lower = 0.0, upper = 0.0;
  // Ring b (xz plane) at spacing 1.7 > 2(R - r) = 1.6 from ring a: the tubes overlap by 0.1.
  core_distance_bounds(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 1.0, Eigen::Vector3d(1.7, 0, 0),
                       Eigen::Vector3d(0.5 * M_PI, 0, 0), 1.0, 1 << 15, lower, upper);
  EXPECT_NEAR(upper - 0.4, -0.1, 1e-6);
  EXPECT_LT(upper - 0.4, 0.0);
}

// The broad phase changes which pairs are looked at, not the result: on the 16-element threefold
// supercell (208 bodies with images) in a perturbed, sheared state with pairs inside a wide d_hat,
// the energy, gradient, Hessian (exact and projected), smallest distance and CCD step equal the
// contact term's all-pairs ones, and a limit found both ways is the same. The reference fails
// when a pair is dropped (a candidate list without the node ring's pairs changes the energy).
TEST(PeriodicRigidCell, BroadPhaseGivesTheAllPairsResults) {
  RigidCellSpec spec = supercell(threefold_cell(kRing, kRing, 1.5), 2, 2);
  spec.activation_distance = 0.08;  // many pairs within reach at rest
  RigidCellSpec reference = spec;
  reference.broad_phase = false;
  const PeriodicRigidCell broad(spec), all(reference);
  ASSERT_EQ(broad.num_bodies(), 208);
  Eigen::Matrix2d F;
  F << 1.01, 0.004, -0.003, 0.995;
  Vector y = broad.rest_free_state();
  for (Eigen::Index i = 0; i < y.size(); ++i) y[i] += 0.004 * std::sin(1.7 * static_cast<double>(i));
  const Vector x = broad.full_state(y, F);
  int all_pairs = 0;
  for (int a = 0; a < broad.num_bodies(); ++a)
    for (int b = a + 1; b < broad.num_bodies(); ++b) all_pairs += (a < broad.num_elements() || b < broad.num_elements());
  const std::size_t candidates = broad.candidate_pairs(x, broad.activation_distance()).size();
  std::printf("broad phase: %zu candidates of %d master-master and master-image pairs\n", candidates, all_pairs);
  EXPECT_LT(candidates, static_cast<std::size_t>(all_pairs) / 10);
  // A position the grid cannot index (an optimizer's failed trial) makes every pair a candidate.
  Vector broken = x;
  broken[6 * 3 + 1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(broad.candidate_pairs(broken, broad.activation_distance()).size(), static_cast<std::size_t>(all_pairs));
  for (const HessianMode mode : {HessianMode::exact, HessianMode::projected}) {
    const ReducedContact cb = reduced_contact(broad, x, true, mode), ca = reduced_contact(all, x, true, mode);
    ASSERT_GT(cb.energy, 0.0);
    EXPECT_EQ(cb.energy, ca.energy);
    EXPECT_EQ(cb.full_gradient, ca.full_gradient);
    EXPECT_LE((cb.hessian - ca.hessian).lpNorm<Eigen::Infinity>(), 1e-13 * ca.hessian.lpNorm<Eigen::Infinity>());
    EXPECT_LE(Matrix(cb.full_hessian - ca.full_hessian).lpNorm<Eigen::Infinity>(),
              1e-13 * ca.hessian.lpNorm<Eigen::Infinity>());
  }
  EXPECT_EQ(contact_energy(broad, x), contact_energy(all, x));
  EXPECT_EQ(smallest_distance(broad, x, 0.08), smallest_distance(all, x, 0.08));
  // CCD: a step that closes gaps (masters pushed together) is cut the same.
  Vector dy = Vector::Zero(y.size());
  for (Eigen::Index i = 0; i < y.size(); ++i) dy[i] = 0.05 * std::cos(0.9 * static_cast<double>(i));
  const Vector dx = broad.basis() * dy;
  const double step = contact_max_step(broad, x, dx);
  EXPECT_LT(step, 1.0);
  EXPECT_EQ(step, contact_max_step(all, x, dx));
  // Every pair the contact term finds within d_hat is a candidate; there are several, each adding a
  // positive barrier, so the energy comparison above sees any pair the broad phase drops.
  const std::vector<std::pair<int, int>> pairs = broad.candidate_pairs(x, broad.activation_distance());
  const std::vector<tori::TorusPair> active =
      all.contact().close_pairs(x, all.radii_parameters(), all.activation_distance(), false);
  EXPECT_GE(active.size(), 4u);
  for (const tori::TorusPair& pair : active)
    EXPECT_TRUE(std::binary_search(pairs.begin(), pairs.end(), std::make_pair(pair.a, pair.b)))
        << pair.a << "-" << pair.b;
  // A limit both ways (the threefold mail at 30 degrees, uniaxial).
  const PeriodicRigidCell mail(threefold_cell(kRing, kRing, 1.5));
  RigidCellSpec mail_all_spec = threefold_cell(kRing, kRing, 1.5);
  mail_all_spec.broad_phase = false;
  const PeriodicRigidCell mail_all(mail_all_spec);
  const LimitPoint lb = find_limit(mail, uniaxial_path(M_PI / 6.0), rest_equilibrium(mail));
  const LimitPoint la = find_limit(mail_all, uniaxial_path(M_PI / 6.0), rest_equilibrium(mail_all));
  std::printf("threefold 30 deg: broad phase %.12f, all pairs %.12f\n", lb.strain, la.strain);
  ASSERT_TRUE(lb.locked && la.locked);
  EXPECT_EQ(lb.strain, la.strain);
}

}  // namespace
}  // namespace tailor::interlocking::periodic_cell_test
