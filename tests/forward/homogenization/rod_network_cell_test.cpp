// Rod-network cells (forward/homogenization/rod_network_cell.hpp) against closed forms nobody here
// wrote: Gibson & Ashby, "Cellular Solids" (2nd ed., 1997), section 4.3 (regular honeycomb,
// in-plane moduli by wall bending, eq. 4.4 and 4.5, with the axial correction of eq. 4.13), and
// Euler-Bernoulli beam theory (the square grid's stretch and shear). Membrane stiffness C is
// force per length (docs/homogenization.md, "Rod-network cells").
#include "forward/homogenization/rod_network_cell.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "adjoint/derivative_check.hpp"
#include "forward/core/assembler.hpp"
#include "forward/homogenization/engineering_constants.hpp"

namespace tailor::rod_network_cell_test {
namespace {

constexpr double kE = 1.0, kNu = 0.3, kG = kE / (2.0 * (1.0 + kNu));

double second_moment(double a) { return M_PI * std::pow(a, 4) / 4.0; }

// Discretization factor of a bar of m edges in the linear bending of a guided (clamped-sliding)
// beam: the rod's bending is a chain of rotational springs (compliance L/B inside, L/(2B) at the
// rigid joints), i.e. the trapezoidal rule for the tip deflection's integral of M(s)(l - s) / B,
// whose error for the linear moment is exactly 2/m^2 of the deflection.
double bending_discretization(int m) { return 1.0 + 2.0 / (m * m); }

TEST(RodNetworkCell, SquareLatticeStretchesAlongTheBarsAndShearsByBending) {
  // Square grid of cell size l: along the bars C_11 = C_22 = E pi a^2 / l (so E*/E_s =
  // pi a^2 / (l depth) for a sheet of depth `depth`); no Poisson coupling; shear bends every bar
  // as a guided beam with end offset gamma l / 2, so C_33 = 6 E I / l^3.
  const double l = 2.0, a = 0.02;
  const int m = 8;
  RodNetworkCell cell(square_rod_lattice(l, a, kE, kG, m));
  const RodNetworkHomogenization h = cell.solve();
  const double stretch = kE * M_PI * a * a / l;
  EXPECT_NEAR(h.stiffness(0, 0) / stretch, 1.0, 1e-10);
  EXPECT_NEAR(h.stiffness(1, 1) / stretch, 1.0, 1e-10);
  EXPECT_LT(std::abs(h.stiffness(0, 1)), 1e-10 * stretch);
  EXPECT_LT(std::abs(h.stiffness(0, 2)), 1e-10 * stretch);
  const double shear = 6.0 * kE * second_moment(a) / std::pow(l, 3);
  EXPECT_NEAR(h.stiffness(2, 2) * bending_discretization(m) / shear, 1.0, 1e-10);
  EXPECT_LT(h.symmetry_error, 1e-10);
}

TEST(RodNetworkCell, SquareLatticeDiagonalModulusTendsToTheBendingLimitAsSlendernessGrows) {
  // E(45 deg) = 1 / (S_11 / 2 + S_33 / 4) = 24 E I / l^3 / (1 + 3 (a/l)^2) for EB bars (the
  // stretch compliance is the correction); the relative error to the slender limit 24 E I / l^3
  // must fall by 4 per halving of a/l (to the discretization factor 2/m^2, removed here).
  const double l = 1.0;
  const int m = 4;
  double previous = 0.0;
  for (const double a : {0.04, 0.02, 0.01}) {
    RodNetworkCell cell(square_rod_lattice(l, a, kE, kG, m));
    const Matrix S = compliance(cell.solve().stiffness);
    const Vector d = plane_direction(2, 0, 1, M_PI / 4);
    const double limit = 24.0 * kE * second_moment(a) / std::pow(l, 3);
    // The discretization multiplies the bending part of the compliance only.
    const double expected = 1.0 / (l / (2.0 * kE * M_PI * a * a) + bending_discretization(m) / limit);
    const double measured = directional_youngs_modulus(S, d);
    EXPECT_NEAR(measured / expected, 1.0, 1e-10) << "a/l = " << a;
    const double error = std::abs(measured * bending_discretization(m) / limit - 1.0);
    std::printf("square a/l = %.3f: E(45) / expected - 1 = %.1e, error to 24 E I / l^3 %.3e\n", a / l,
                measured / expected - 1.0, error);
    const double predicted = 3.0 * a * a / (l * l) / bending_discretization(m);
    EXPECT_NEAR(error, predicted, 0.05 * predicted);
    if (previous > 0.0) {
      EXPECT_NEAR(previous / error, 4.0, 0.2);
    }
    previous = error;
  }
}

TEST(RodNetworkCell, HoneycombMatchesGibsonAshbyInTheSlenderLimit) {
  // Regular honeycomb (h = l, theta = 30 deg): Gibson & Ashby eq. 4.4 for walls of second moment
  // I, per unit depth, E*_1 = E*_2 = 12 E I cos(theta) / ((h + l sin(theta)) l^2 sin^2(theta))
  // = 27.71 E I / l^3 (2.31 E (t/l)^3 for I = t^3/12; for a rod of radius a, I = pi a^4 / 4); the
  // walls' axial stretch adds cot^2(theta) 12 I / (A l^2) = 9 (a/l)^2 to the compliance (eq. 4.13
  // without its shear term: Euler-Bernoulli rods). Tolerance: the measured C_11 equals the
  // corrected form times the bar discretization 1 + 2/m^2 to 1e-10; the uncorrected form is
  // approached with an error that falls by 4 per halving of a/l (to within 5 %).
  // E*_1 = 1 / S_11 (uniaxial stress).
  const double l = 1.0, theta = M_PI / 6;
  const int m = 8;
  double previous = 0.0;
  for (const double a : {0.04, 0.02, 0.01}) {
    RodNetworkCell cell(honeycomb_rod_lattice(l, a, kE, kG, m));
    const RodNetworkHomogenization h = cell.solve();
    const double gibson_ashby = 12.0 * kE * second_moment(a) * std::cos(theta) /
                                ((l + l * std::sin(theta)) * l * l * std::pow(std::sin(theta), 2));
    EXPECT_NEAR(gibson_ashby / (kE * second_moment(a) / std::pow(l, 3)), 27.7128, 1e-4);
    const double axial = 12.0 * second_moment(a) / (M_PI * a * a * l * l) / std::pow(std::tan(theta), 2);
    const double corrected = gibson_ashby / (bending_discretization(m) + axial);
    // E*_1 is the modulus under uniaxial stress, 1 / S_11 (C_11 itself is dominated by the
    // walls' stretching: an equibiaxial strain stretches every wall).
    const Matrix S = compliance(h.stiffness);
    const double E1 = directional_youngs_modulus(S, plane_direction(2, 0, 1, 0.0));
    const double E2 = directional_youngs_modulus(S, plane_direction(2, 0, 1, M_PI / 2));
    EXPECT_NEAR(E1 / corrected, 1.0, 1e-10) << "C = \n" << h.stiffness;
    // Regular honeycombs are in-plane isotropic: E_1 = E_2 (eq. 4.5), nu_12 -> 1 (eq. 4.6).
    EXPECT_NEAR(E2 / E1, 1.0, 1e-8);
    EXPECT_NEAR(poisson_ratio(S, plane_direction(2, 0, 1, 0.0), plane_direction(2, 0, 1, M_PI / 2)), 1.0,
                4.0 * axial);
    const double error = std::abs(E1 * bending_discretization(m) / gibson_ashby - 1.0);
    std::printf(
        "honeycomb a/l = %.3f: E1 / (eq. 4.4 corrected) - 1 = %.1e, error to eq. 4.4 %.3e, nu12 - 1 = %.2e\n",
        a / l, E1 / corrected - 1.0, error,
        poisson_ratio(S, plane_direction(2, 0, 1, 0.0), plane_direction(2, 0, 1, M_PI / 2)) - 1.0);
    if (previous > 0.0) {
      EXPECT_NEAR(previous / error, 4.0, 0.2) << "a/l = " << a;
    }
    previous = error;
  }
  EXPECT_LT(previous, 1e-3);  // a/l = 0.01
}

TEST(RodNetworkCell, SupercellGivesTheCellsTensor) {
  // The 2x2 supercell of the square grid (4 joints, 8 bars, images across both faces) must give
  // the 1x1 cell's tensor: the images' offsets follow the macro strain.
  const double l = 1.0, a = 0.03;
  const RodNetwork one = square_rod_lattice(l, a, kE, kG, 4);
  RodNetwork four = one;
  four.lattice = 2.0 * l * Eigen::Matrix2d::Identity();
  four.joints.resize(4, 2);
  four.joints << 0, 0, l, 0, 0, l, l, l;
  four.bars = {{0, 1, {0, 0}}, {1, 0, {1, 0}}, {2, 3, {0, 0}}, {3, 2, {1, 0}},
               {0, 2, {0, 0}}, {2, 0, {0, 1}}, {1, 3, {0, 0}}, {3, 1, {0, 1}}};
  RodNetworkCell small(one), big(four);
  const Matrix C1 = small.solve().stiffness, C4 = big.solve().stiffness;
  EXPECT_LT((C1 - C4).norm(), 1e-9 * C1.norm()) << C1 << "\n" << C4;
}

TEST(RodNetworkCell, PeriodicEnergyDerivativesPass) {
  // Every term of the cell (rods and joints with image members) at a macro-strained, perturbed
  // state, and the reduced energy y -> E(x0(H) + S y) whose gradient and Hessian Newton and the
  // cell problems use, against central differences.
  RodNetworkCell cell(honeycomb_rod_lattice(1.0, 0.05, kE, kG, 3));
  Model& model = cell.model();
  Matrix H(2, 2);
  H << 0.05, 0.02, -0.01, -0.03;
  model.elimination().set_offset(cell.macro_offset(H));
  const int n = cell.num_free();
  const Vector y = 0.02 * Vector::Random(n);
  const Vector x = model.elimination().expand(y);
  for (const auto& term : model.terms()) {
    // The joints read no parameters (their stiffnesses are fixed numbers).
    const bool joint = term->name() == "rod_rigid_joint";
    const EnergyTermCheck c = check_energy_term(*term, x, joint ? Vector() : cell.parameters());
    EXPECT_TRUE(c.passed()) << term->name() << "\n" << c.table();
  }
  ReducedAssembler assembler(model);
  Vector g;
  SparseMatrix hessian = assembler.hessian_pattern_matrix();
  assembler.evaluate(y, cell.parameters(), nullptr, &g, &hessian);
  const Vector dy = Vector::Random(n);
  const auto energy = [&](double t) {
    double e = 0.0;
    assembler.evaluate(y + t * dy, cell.parameters(), &e, nullptr, nullptr);
    return Vector::Constant(1, e);
  };
  const auto gradient = [&](double t) {
    Vector gt;
    assembler.evaluate(y + t * dy, cell.parameters(), nullptr, &gt, nullptr);
    return gt;
  };
  const Vector Hdy = hessian.selfadjointView<Eigen::Upper>() * dy;
  DerivativeCheckOptions options;
  options.initial_step = 1e-2;
  const DerivativeCheck cg =
      check_directional_derivative("gradient", energy, Vector::Constant(1, g.dot(dy)), options);
  EXPECT_TRUE(cg.passed) << cg.message;
  const DerivativeCheck ch = check_directional_derivative("hessian", gradient, Hdy, options);
  EXPECT_TRUE(ch.passed) << ch.message;
  // The check can fail: a Hessian 1e-4 off is caught.
  const DerivativeCheck bad = check_directional_derivative("hessian", gradient, 1.0001 * Hdy, options);
  EXPECT_FALSE(bad.passed);
}

TEST(RodNetworkCell, RejectsBadNetworks) {
  RodNetwork n = square_rod_lattice(1.0, 0.01, kE, kG, 4);
  n.bars[0].to = 3;
  EXPECT_THROW(RodNetworkCell{n}, std::invalid_argument);
  n = square_rod_lattice(1.0, 0.01, kE, kG, 4);
  n.bars[0].shift.setZero();  // a bar from the joint to itself
  EXPECT_THROW(RodNetworkCell{n}, std::invalid_argument);
  n = square_rod_lattice(1.0, 0.01, kE, kG, 4);
  n.joints.resize(2, 2);
  n.joints << 0, 0, 0.5, 0.5;  // joint 1 is on no bar
  EXPECT_THROW(RodNetworkCell{n}, std::invalid_argument);
  n = square_rod_lattice(1.0, -0.01, kE, kG, 4);
  EXPECT_THROW(RodNetworkCell{n}, std::invalid_argument);
  // Pin-jointed-like mechanism: a single bar along x cannot carry y strain.
  n = square_rod_lattice(1.0, 0.01, kE, kG, 4);
  n.bars.pop_back();
  RodNetworkCell mechanism(n);
  EXPECT_THROW(mechanism.solve(), std::runtime_error);
}

}  // namespace
}  // namespace tailor::rod_network_cell_test
