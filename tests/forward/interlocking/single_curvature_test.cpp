// Periodic single curvature: the cylinder's periodicity map (image rotations log(Q exp(w)) with
// exact first and second derivatives, checked by central differences at generic, small and
// near-pi angles), the reduced contact energy through it (check_energy_term), and bending limits:
// symmetry, the symmetric branch's closed form as a lower bound, every state certified apart.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>

#include "adjoint/derivative_check.hpp"
#include "forward/interlocking/cell_patterns.hpp"
#include "forward/interlocking/curved_periodicity.hpp"
#include "forward/interlocking/interpenetration_check.hpp"
#include "forward/interlocking/single_curvature_limit.hpp"
#include "forward/rigid/rotation.hpp"

namespace tailor::interlocking::single_curvature_test {
namespace {

const tori::TorusShape kRing{1.0, 0.2};
constexpr double kSpacing = 1.5;

// Largest relative error of the image rotation's Jacobian and Hessian against central differences
// (step h) at z = (w_master, kappa) for the screw of `shift`; `scale` multiplies the analytic
// Hessian (a wrong one must fail).
double image_rotation_error(const Eigen::Vector3d& w_master, double kappa, double angle, const Eigen::Vector2d& shift,
                            double h, double scale = 1.0) {
  const auto at = [&](const Eigen::Vector4d& z, const Eigen::Vector3d& near) {
    const CylinderScrew s = cylinder_screw(z[3], angle, Eigen::Vector3d::Zero(), shift);
    return image_rotation(s.Q, s.dQ, s.d2Q, z.head<3>(), near);
  };
  const Eigen::Vector4d z(w_master.x(), w_master.y(), w_master.z(), kappa);
  const CylinderScrew s0 = cylinder_screw(kappa, angle, Eigen::Vector3d::Zero(), shift);
  const ImageRotation r = at(z, w_master + kappa * s0.axis_rate);
  double error = 0.0;
  for (int a = 0; a < 4; ++a) {
    Eigen::Vector4d dz = Eigen::Vector4d::Zero();
    dz[a] = h;
    const ImageRotation p = at(z + dz, r.w), m = at(z - dz, r.w);
    const Eigen::Vector3d fd_w = (p.w - m.w) / (2.0 * h);
    error = std::max(error, (fd_w - r.jacobian.col(a)).norm() / std::max(1.0, r.jacobian.norm()));
    for (int mm = 0; mm < 3; ++mm) {
      const Eigen::Vector4d fd_j = (p.jacobian.row(mm) - m.jacobian.row(mm)).transpose() / (2.0 * h);
      const Eigen::Vector4d exact = scale * r.hessian[static_cast<std::size_t>(mm)].col(a);
      error = std::max(error, (fd_j - exact).norm() / std::max(1.0, r.hessian[static_cast<std::size_t>(mm)].norm()));
    }
  }
  return error;
}

// Reference: central differences (h = 1e-5, truncation ~1e-10). Generic angles, a nearly identity
// image rotation (|w_j| ~ 1e-7: the small-angle series of R(w)), and |w_j| = pi -+ 1e-4 (where
// log's branch formulas degenerate; the inverse-function form does not).
TEST(SingleCurvature, ImageRotationDerivativesMatchDifferences) {
  const double angle = 0.3, kappa = 0.4;
  const Eigen::Vector2d shift(1.7, -0.6);
  const CylinderScrew s = cylinder_screw(kappa, angle, Eigen::Vector3d::Zero(), shift);
  const Eigen::Vector3d generic(0.3, -0.2, 0.5);
  const Eigen::Vector3d small = -kappa * s.axis_rate + Eigen::Vector3d(2e-7, -1e-7, 3e-7);
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, 0.9, -0.4).normalized();
  const auto master_for = [&](const Eigen::Vector3d& w_image) {
    return rigid::rotation_vector(s.Q.transpose() * rigid::rotation_matrix(w_image));
  };
  const Eigen::Vector3d below_pi = master_for((M_PI - 1e-4) * n), above_pi = master_for((M_PI + 1e-4) * n);
  for (const Eigen::Vector3d& w : {generic, small, below_pi, above_pi}) {
    const ImageRotation r = image_rotation(s.Q, s.dQ, s.d2Q, w, w + kappa * s.axis_rate);
    const double error = image_rotation_error(w, kappa, angle, shift, 1e-5);
    std::printf("image rotation |w_j| = %.8f: derivative error %.2e\n", r.w.norm(), error);
    EXPECT_LT(error, 1e-7);
  }
  EXPECT_GT(image_rotation_error(generic, kappa, angle, shift, 1e-5, 1.001), 1e-5);  // a wrong Hessian fails
  // The screw itself: R(w_j) = Q R(w_i) and dQ, db against differences, in the series region too.
  for (const double k : {0.4, 1e-3, 0.0}) {
    const double h = 1e-6;
    const Eigen::Vector3d anchor(0.1, -0.2, 0.05);
    const CylinderScrew c = cylinder_screw(k, angle, anchor, shift), p = cylinder_screw(k + h, angle, anchor, shift),
                        m = cylinder_screw(k - h, angle, anchor, shift);
    EXPECT_LT((c.dQ - (p.Q - m.Q) / (2 * h)).norm(), 1e-8);
    EXPECT_LT((c.d2Q - (p.dQ - m.dQ) / (2 * h)).norm(), 1e-8);
    EXPECT_LT((c.db - (p.b - m.b) / (2 * h)).norm(), 1e-8);
  }
}

// At kappa = 0 the map is the flat cell's at F = I; at kappa > 0 every image of the anchor lies on
// the cylinder of radius 1/kappa through the anchor (axis along e), turned by its arc length.
TEST(SingleCurvature, ScrewMapIsFlatAtZeroAndACylinderOtherwise) {
  const PeriodicRigidCell cell(square_ring_cell(kRing, kRing, kRing, kSpacing));
  const double angle = 0.25;
  const SingleCurvatureCell curved(cell, angle);
  Vector y = cell.rest_free_state();
  y += 0.01 * Vector::LinSpaced(y.size(), -1.0, 1.0);
  EXPECT_LT((curved.full_state(y, 0.0) - cell.full_state(y, Eigen::Matrix2d::Identity())).norm(), 1e-14);
  const double kappa = 0.3;
  const Vector x = curved.full_state(y, kappa);
  const Eigen::Vector3d d(std::cos(angle), std::sin(angle), 0.0), e(-std::sin(angle), std::cos(angle), 0.0);
  const Eigen::Vector3d c = x.segment<3>(0) + Eigen::Vector3d::UnitZ() / kappa;  // anchor 0 at rest
  for (int body = cell.num_elements(); body < cell.num_bodies(); ++body) {
    if (cell.master(body) != 0) continue;
    const Eigen::Vector3d r = x.segment<3>(6 * body) - c;
    EXPECT_NEAR((r - r.dot(e) * e).norm(), 1.0 / kappa, 1e-12);
    const Eigen::Vector2d t = cell.spec().lattice * cell.shift(body).cast<double>();
    EXPECT_NEAR(r.dot(e), t.dot(e.head<2>()), 1e-12);
    const double turned = std::atan2(r.dot(d), -r.z());
    EXPECT_NEAR(turned, kappa * t.dot(d.head<2>()), 1e-12);
  }
  // dx/dkappa against differences.
  const SingleCurvatureCell::MapDerivatives m = curved.map(y, kappa);
  const double h = 1e-6;
  const Vector fd = (curved.full_state(y, kappa + h) - curved.full_state(y, kappa - h)) / (2 * h);
  EXPECT_LT((m.curvature_derivative - fd).norm(), 1e-7 * fd.norm());
}

// The symmetric branch of a periodic chain bent along itself (flat rings at arc spacing 2 s on the
// cylinder of radius rho = 1/kappa through their centres, upright links between them in the
// bending plane; the flat rings tangent to the cylinder, each link on the ray from the axis at half
// the angle, phi = s kappa, free along it). A flat ring's core crosses the link's plane at
// A = (R, 0, 0) (ring at the origin), running across it, and the link keeps the gap
// R - |A - P| - 2 r with its centre P on that ray; the best P is A's foot on the ray,
// |A - P| = rho sin(phi) - R cos(phi), so this configuration is admissible while
//   sin(s kappa) / kappa - R cos(s kappa) <= R - 2 r - d_hat / 2
// (kappa -> 0: s - R <= R - 2 r, the flat chain's spacing; equality solved by bisection). Tilting
// the flat rings about y in the bending plane does not help (checked numerically: the chord
// between the two crossings is shortest untilted), but the periodic cells leave it: nodes tilt
// about the chain's axis and links shift sideways, so the cells lock later (square net) or not at
// all (a lone chain): this curvature is a lower bound of their limits, not the limit.
double symmetric_branch_curvature(double R, double r, double s, double d_hat) {
  const auto f = [&](double k) { return std::sin(s * k) / k - R * std::cos(s * k) - (R - 2.0 * r - 0.5 * d_hat); };
  double lo = 1e-6, hi = 1.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) (f(0.5 * (lo + hi)) < 0.0 ? lo : hi) = 0.5 * (lo + hi);
  return 0.5 * (lo + hi);
}

void expect_apart(const SingleCurvatureCell& curved, const LimitPoint& p, double sign) {
  const ClearanceReport c = check_clearance(curved.cell(), curved.full_state(p.y, sign * p.strain), 1 << 14);
  EXPECT_TRUE(c.apart()) << "certified clearance " << c.min_lower;
}

// The equilibrium's energy in the master DOFs through the nonlinear map: value, gradient, Hessian,
// dE/dkappa and the mixed block (check_energy_term) at a chain state bent past its equilibrium so
// that pairs are inside d_hat; the chain stays unlocked past the symmetric branch's curvature.
TEST(SingleCurvature, ChainEnergyPassesTheDerivativeCheckAndBendsPastTheSymmetricBranch) {
  const PeriodicRigidCell cell(chain_cell(kRing, kRing, kSpacing, 10.0 * kSpacing));
  const double lower = symmetric_branch_curvature(1.0, 0.2, kSpacing, cell.activation_distance());
  const SingleCurvatureCell along(cell, 0.0);
  const Vector y_rest = rest_equilibrium(cell);
  LimitOptions options;
  options.max_strain = 0.47;
  const LimitPoint p = find_single_curvature_limit(along, y_rest, options, 1.0);
  std::printf("periodic chain: free up to %.2f (%s, %d solves); symmetric branch %.10f\n", p.strain,
              p.status.c_str(), p.solves, lower);
  EXPECT_FALSE(p.locked);
  EXPECT_GT(p.strain, lower);
  EXPECT_GT(std::abs(cell.master_state(p.y)[3]), 0.1);  // the flat ring tilts about the chain's axis
  expect_apart(along, p, 1.0);
  const SingleCurvatureContactTerm term(along);
  Vector kappa(1);
  for (kappa[0] = p.strain; term.value(p.y, kappa) == 0.0 && kappa[0] < p.strain + 0.1;) kappa[0] += 5e-4;
  ASSERT_GT(term.value(p.y, kappa), 0.0);
  ASSERT_TRUE(std::isfinite(term.value(p.y, kappa)));
  DerivativeCheckOptions check;
  check.state_scale = 0.1;
  check.initial_step = 1e-5;
  const EnergyTermCheck c = check_energy_term(term, p.y, kappa, check);
  std::printf("%s", c.table().c_str());
  EXPECT_TRUE(c.passed());
}

// Symmetry: the square net with equal links bends alike along x and y and up and down (the same
// limit to round-off, refined), later than the symmetric branch of its chains (its nodes tilt).
TEST(SingleCurvature, SquareNetBendsSymmetrically) {
  const PeriodicRigidCell cell(square_ring_cell(kRing, kRing, kRing, kSpacing));
  const double lower = symmetric_branch_curvature(1.0, 0.2, kSpacing, cell.activation_distance());
  const Vector y_rest = rest_equilibrium(cell);
  std::vector<LimitPoint> b;
  for (const auto& [angle, sign] : {std::pair{0.0, 1.0}, std::pair{0.5 * M_PI, 1.0}, std::pair{0.0, -1.0}}) {
    const SingleCurvatureCell curved(cell, angle);
    b.push_back(find_single_curvature_limit(curved, y_rest, LimitOptions{}, sign));
    std::printf("square net bending at %.0f deg, sign %+.0f: %.12f (%s, %d solves, %zu active)\n", angle * 180 / M_PI,
                sign, b.back().strain, b.back().status.c_str(), b.back().solves, b.back().active.size());
    ASSERT_TRUE(b.back().locked && b.back().refined);
    expect_apart(curved, b.back(), sign);
  }
  EXPECT_NEAR(b[1].strain, b[0].strain, 1e-9);
  EXPECT_NEAR(b[2].strain, b[0].strain, 1e-9);
  EXPECT_GT(b[0].strain, lower);
}

}  // namespace
}  // namespace tailor::interlocking::single_curvature_test
