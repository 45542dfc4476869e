// Newton's stopping rule at the round-off floor (forward/solve/newton.hpp, docs/performance.md
// "The round-off floor"), on inputs whose answers are known without this code:
//  - a Neo-Hookean bar in uniaxial tension against the closed-form uniaxial stretch of the
//    stable Neo-Hookean density (linear tets reproduce a homogeneous deformation exactly);
//  - a two-material bar (moduli contrast 1e6 and 1e12, the stiff part at the root) in tension
//    against springs in series, u = T (L_1 / E_1 + L_2 / E_2) (exact for linear tets, nu = 0);
//  - a nu = 0.45 Neo-Hookean cantilever (plane strain) under a small tip load against
//    Timoshenko's tip deflection, to the discretization error (Richardson's estimate from two
//    meshes);
// each ends converged or round_off_floor (not at the iteration limit, not ill_conditioned) and
// matches its reference to the accuracy the floor allows; and
//  - a stiff block (modulus 1e16 times the support's) carried by a soft support: the round-off
//    of the block's forces moves it by more than the load does, so the answer has no digits (a
//    block's modulus moved by 4 units in the last place changes it at O(1)): ill_conditioned.
// Run forward_solve_tests --gtest_filter='NewtonFloor*' to see each case's figures.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>

#include "../../support/fem_fixtures.hpp"
#include "forward/fem/loads.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::newton_floor_test {
namespace {

using namespace tailor::testing;

// A box [0, L] x [0, 1] x [0, 1] of tets under the nominal (dead) traction T along x on X = L,
// held by symmetry planes only (u_x = 0 on X = 0, u_y = 0 on Y = 0, u_z = 0 on Z = 0): every
// homogeneous deformation diag(a, b, b) satisfies them, so linear tets reproduce uniaxial
// stress exactly. The modulus may depend on the element's centroid x; one Poisson ratio.
struct UniaxialBar {
  Mesh mesh;
  Model model;
  Vector rest;  // free unknowns at rest
  Vector p;
  std::vector<int> tip;  // vertices on X = L
  double length;

  UniaxialBar(MaterialKind kind, double L, const Eigen::Vector3i& cells, double traction,
              const std::function<double(double)>& modulus, double nu)
      : mesh(box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(L, 1, 1), cells[0], cells[1], cells[2])),
        model(3 * mesh.num_vertices()),
        length(L) {
    const int m = mesh.num_elements();
    model.parameter_layout().add("youngs_modulus", m);
    model.parameter_layout().add("poisson_ratio", m);
    model.add(elastic_term<3>(mesh, kind));
    const Eigen::MatrixXi end = boundary_facets_where(mesh, [L](const Eigen::VectorXd& X) { return X[0] > L - 1e-9; });
    model.add(std::make_unique<ExternalForceTerm>(traction_forces(mesh, end, Eigen::Vector3d(traction, 0, 0))));
    std::vector<int> fixed;
    for (int v = 0; v < mesh.num_vertices(); ++v)
      for (int k = 0; k < 3; ++k)
        if (mesh.rest_positions(v, k) < 1e-9) fixed.push_back(3 * v + k);
    for (int v = 0; v < mesh.num_vertices(); ++v)
      if (mesh.rest_positions(v, 0) > L - 1e-9) tip.push_back(v);
    const Vector x0 = rest_state(mesh);
    model.set_elimination(Elimination::dirichlet(fixed, x0));
    rest = model.elimination().restrict_state(x0);
    p.resize(2 * m);
    for (int e = 0; e < m; ++e) {
      double cx = 0.0;
      for (int a = 0; a < 4; ++a) cx += 0.25 * mesh.rest_positions(mesh.elements(e, a), 0);
      p[e] = modulus(cx);
    }
    p.tail(m).setConstant(nu);
  }
  // Mean x-displacement of the loaded end.
  double tip_displacement(const Vector& y) const {
    const Vector x = model.state(y, p);
    double u = 0.0;
    for (int v : tip) u += x[3 * v] - mesh.rest_positions(v, 0);
    return u / static_cast<double>(tip.size());
  }
};

struct Case {
  NewtonResult newton;
  double tip = 0.0;
  double reference = 0.0;
  double error() const { return std::abs(tip - reference) / std::abs(reference); }
};

void print(const std::string& name, const Case& c) {
  std::cout << std::scientific << std::setprecision(2) << name << ": " << to_string(c.newton.status) << " after "
            << c.newton.iterations << " iterations, residual " << c.newton.final_residual << " (initial "
            << c.newton.initial_residual << "), floor " << c.newton.residual_floor << ", accuracy " << c.newton.accuracy << ", tip " << std::setprecision(12) << c.tip << " reference " << c.reference
            << std::setprecision(2) << ", relative error " << c.error() << "\n  " << c.newton.message << "\n";
}

// Stable Neo-Hookean (forward/fem/materials/neo_hookean.hpp) in uniaxial nominal stress T:
// F = diag(a, b, b) with P_22 = 0 and P_11 = T, P = (4/3) mu I_C/(I_C + 1) F + s cof F,
// s = (lambda + 5/6 mu)(J - 1) - mu, cof F = diag(b^2, a b, a b). Returns a.
double neo_hookean_uniaxial_stretch(double E, double nu, double T) {
  const double mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  auto residual = [&](double a, double b) {
    const double I = a * a + 2 * b * b, J = a * b * b, c = 4.0 / 3.0 * mu * I / (I + 1);
    const double s = (lambda + 5.0 / 6.0 * mu) * (J - 1) - mu;
    return Eigen::Vector2d(c * a + s * b * b - T, c + s * a);  // P_11 - T, P_22 / b
  };
  Eigen::Vector2d ab(1.0 + T / E, 1.0 - nu * T / E);
  for (int it = 0; it < 50; ++it) {
    const Eigen::Vector2d r = residual(ab[0], ab[1]);
    Eigen::Matrix2d J;
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector2d d = ab;
      const double h = 1e-7 * std::abs(ab[k]);
      d[k] += h;
      J.col(k) = (residual(d[0], d[1]) - r) / h;
    }
    const Eigen::Vector2d step = J.lu().solve(-r);
    ab += step;
    if (step.norm() < 1e-17) break;
  }
  return ab[0];
}

Case solve_bar(UniaxialBar& bar, double reference) {
  NewtonSolver newton(bar.model);
  Vector y = bar.rest;
  Case c;
  c.newton = newton.solve(bar.p, y);
  c.tip = bar.tip_displacement(y);
  c.reference = reference;
  return c;
}

// What the floor lets a displacement be known to: the estimated error Newton reports where the
// residual alone does not certify the solution, and never less than the precision the
// coordinates are stored to (100 eps times the largest coordinate).
double allowed_error(const Case& c, double coordinates) {
  return std::max(10.0 * c.newton.accuracy, 100.0 * std::numeric_limits<double>::epsilon() * coordinates);
}

// The floor ends the solve early enough: not at the iteration limit, not ill_conditioned, and
// not before the first step (a start within its floor that is not the answer).
void expect_floor_or_converged(const Case& c) {
  EXPECT_TRUE(c.newton.converged()) << c.newton.report();
  EXPECT_GE(c.newton.iterations, 1) << c.newton.report();
  EXPECT_LE(c.newton.iterations, 10) << c.newton.report();
}

TEST(NewtonFloor, NeoHookeanBarInTensionReachesTheUniaxialStretch) {
  // T / E = 1e-5 ran to the iteration limit before: the stable Neo-Hookean's element energies
  // cancel O(mu) terms, so the line search could not see the last steps' decrease.
  for (const double load : {1e-5, 1e-7}) {
    const double E = 1.0, nu = 0.3, L = 4.0;
    UniaxialBar bar(MaterialKind::neo_hookean, L, Eigen::Vector3i(16, 4, 4), load, [E](double) { return E; }, nu);
    const double a = neo_hookean_uniaxial_stretch(E, nu, load);
    const Case c = solve_bar(bar, (a - 1.0) * L);
    print("NH bar, T/E " + std::to_string(load), c);
    expect_floor_or_converged(c);
    EXPECT_LE(std::abs(c.tip - c.reference), allowed_error(c, 1.0 + L)) << c.newton.report();
  }
}

TEST(NewtonFloor, StiffRootContrastReachesSeriesSprings) {
  // Before, 1e6 ended ill_conditioned ("no reliable digits") with the tip right to 2e-10, and
  // 1e12 ended at iteration 0 with no displacement (the load is below the stiff part's force
  // round-off, compared norm against norm).
  for (const double contrast : {1e6, 1e12}) {
    const double soft = 1.0, T = 1e-6, L = 4.0, root = 2.0;
    UniaxialBar bar(MaterialKind::linear, L, Eigen::Vector3i(16, 4, 4), T,
                    [&](double x) { return x < root ? soft * contrast : soft; }, 0.0);
    const Case c = solve_bar(bar, T * (root / (soft * contrast) + (L - root) / soft));
    print("stiff root, contrast " + std::to_string(contrast), c);
    expect_floor_or_converged(c);
    EXPECT_LE(std::abs(c.tip - c.reference), allowed_error(c, 1.0 + L)) << c.newton.report();
    EXPECT_LT(c.error(), 1e-8);
  }
}

// Soft support on [0, 2], a block `contrast` times stiffer on [2, 4], the traction on the block.
// `ulps` moves the block's modulus by that many units in the last place: a change of round-off
// size, which moves the exact answer by 1e-16 of itself.
Case solve_block(double contrast, double traction, int ulps = 0) {
  const double soft = 1.0, L = 4.0, root = 2.0;
  UniaxialBar bar(MaterialKind::linear, L, Eigen::Vector3i(16, 4, 4), traction,
                  [&](double x) {
                    return x < root ? soft : soft * contrast * (1.0 + ulps * std::numeric_limits<double>::epsilon());
                  },
                  0.0);
  return solve_bar(bar, traction * (root / soft + (L - root) / (soft * contrast)));
}

TEST(NewtonFloor, StiffBlockOnSoftSupport) {
  // 1e12: the block's force round-off is 1e5 times the load, yet lands mostly on its own DOFs;
  // the answer keeps about two digits, and the reported accuracy says so.
  const Case some = solve_block(1e12, 1e-6);
  print("stiff block, contrast 1e12", some);
  expect_floor_or_converged(some);
  EXPECT_LE(std::abs(some.tip - some.reference), allowed_error(some, 5.0)) << some.newton.report();
  EXPECT_LT(some.error(), 0.1);
  // 1e15 and 1e16: the round-off moves the block by as much as the load does. The answer has no
  // digits: it is wrong at O(1) (a few percent of the reference), and moving the block's modulus
  // by 4 ulps changes it by 9 % (1e15) and 17 times (1e16) of itself.
  for (const double contrast : {1e15, 1e16}) {
    const Case none = solve_block(contrast, 1e-6);
    const Case perturbed = solve_block(contrast, 1e-6, 4);
    print("stiff block, contrast " + std::to_string(contrast), none);
    print("  block modulus 4 ulps larger", perturbed);
    EXPECT_EQ(none.newton.status, NewtonStatus::ill_conditioned) << none.newton.report();
    EXPECT_FALSE(none.newton.converged());
    EXPECT_GT(none.error(), 0.5);
    EXPECT_GT(std::abs(perturbed.tip - none.tip), 0.05 * std::abs(none.tip));
    EXPECT_NE(none.newton.message.find("no reliable digits"), std::string::npos) << none.newton.message;
  }
}

// A plane-strain cantilever [0, L] x [0, t], clamped at X = 0, under the total shear load P
// (per unit thickness) spread uniformly over X = L. Returns the mean y-deflection of that end.
Case solve_cantilever(MaterialKind kind, double E, double nu, double P, int nx, int ny, NewtonOptions options = {}) {
  const double L = 10.0, t = 1.0;
  const Mesh mesh = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(L, t), nx, ny);
  Model model(2 * mesh.num_vertices());
  const int m = mesh.num_elements();
  model.parameter_layout().add("youngs_modulus", m);
  model.parameter_layout().add("poisson_ratio", m);
  model.add(elastic_term<2>(mesh, kind));
  const Eigen::MatrixXi end = boundary_facets_where(mesh, [L](const Eigen::VectorXd& X) { return X[0] > L - 1e-9; });
  model.add(std::make_unique<ExternalForceTerm>(traction_forces(mesh, end, Eigen::Vector2d(0, -P / t))));
  std::vector<int> fixed, tip;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.rest_positions(v, 0) < 1e-9) fixed.insert(fixed.end(), {2 * v, 2 * v + 1});
    if (mesh.rest_positions(v, 0) > L - 1e-9) tip.push_back(v);
  }
  const Vector x0 = rest_state(mesh);
  model.set_elimination(Elimination::dirichlet(fixed, x0));
  Vector p(2 * m);
  p.head(m).setConstant(E);
  p.tail(m).setConstant(nu);
  NewtonSolver newton(model, options);
  Vector y = model.elimination().restrict_state(x0);
  Case c;
  c.newton = newton.solve(p, y);
  const Vector x = model.state(y, p);
  for (int v : tip) c.tip -= (x[2 * v + 1] - mesh.rest_positions(v, 1)) / static_cast<double>(tip.size());
  // Timoshenko, plane strain (E' = E / (1 - nu^2)), shear coefficient 5/6 of a rectangle.
  const double Ep = E / (1 - nu * nu), G = E / (2 * (1 + nu)), I = t * t * t / 12;
  c.reference = P * L * L * L / (3 * Ep * I) + P * L / (5.0 / 6.0 * G * t);
  return c;
}

TEST(NewtonFloor, NearlyIncompressibleCantileverReachesTimoshenko) {
  // nu = 0.45, a load small enough for the residual to reach its floor above the tolerance: the
  // 80 x 8 mesh ran to the iteration limit before.
  const double P = 1e-6;
  const Case coarse = solve_cantilever(MaterialKind::neo_hookean, 1.0, 0.45, P, 40, 4);
  const Case fine = solve_cantilever(MaterialKind::neo_hookean, 1.0, 0.45, P, 80, 8);
  print("cantilever nu 0.45, 40 x 4", coarse);
  print("cantilever nu 0.45, 80 x 8", fine);
  expect_floor_or_converged(coarse);
  expect_floor_or_converged(fine);
  // Linear triangles lock in bending at nu = 0.45 (14 % low on 80 x 8): the discretization error
  // of the finer mesh is within the change from the coarser one (convergence of order >= 1).
  EXPECT_LT(fine.error(), coarse.error());
  EXPECT_LE(std::abs(fine.tip - fine.reference), std::abs(fine.tip - coarse.tip));
  // To the floor's accuracy, the discrete solution is the same mesh's linear-elastic one (at
  // this load the two materials differ by O(P / E) = 1e-6 relative): a refined reference from
  // the same code, one factorization of a constant stiffness.
  const Case linear = solve_cantilever(MaterialKind::linear, 1.0, 0.45, P, 80, 8);
  ASSERT_TRUE(linear.newton.converged()) << linear.newton.report();
  std::cout << "  linear material, 80 x 8: tip " << std::setprecision(12) << linear.tip << ", relative difference "
            << std::setprecision(2) << std::abs(fine.tip - linear.tip) / std::abs(linear.tip) << "\n";
  EXPECT_LT(std::abs(fine.tip - linear.tip), 1e-5 * std::abs(linear.tip));
}

}  // namespace
}  // namespace tailor::newton_floor_test
