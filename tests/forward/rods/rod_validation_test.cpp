// Validation of the discrete elastic rod against closed-form theory:
//  - cantilever under a large tip load vs the elastica (elliptic-integral solution, e.g.
//    Bisshopp & Drucker, Q. Appl. Math. 3 (1945) 272), with second-order error decay;
//  - an end moment bends a straight rod into a circular arc of radius EI / M (Euler-Bernoulli);
//  - the Euler buckling load pi^2 EI / L^2 of a pinned-pinned column (Euler 1744), from the
//    bifurcation: the smallest eigenvalue of the exact Hessian of the straight state crosses 0;
//  - a clamped-clamped straight rod twisted by 50 turns: uniform twist, E = GJ Phi^2 / (2 L)
//    (Saint-Venant torsion).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>

#include "forward/core/elimination.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/fem/loads.hpp"
#include "forward/rods/end_moment_term.hpp"
#include "forward/rods/rod_supports.hpp"
#include "forward/solve/newton.hpp"
#include "rod_fixtures.hpp"
#include "tests/forward/rods/elastica.hpp"

namespace tailor::rod_validation_test {
namespace {

using namespace tailor::testing;

// A circular rod of radius r with E chosen so that EI = 1 (I = pi r^4 / 4), G = E / 2.6.
// r = 1e-4 makes the rod practically inextensible (axial strain ~ P r^2 / (4 EI)).
RodMaterial unit_bending_material(double r = 1e-4) {
  RodMaterial m;
  m.radius = r;
  m.youngs_modulus = 4.0 / (M_PI * r * r * r * r);
  m.shear_modulus = m.youngs_modulus / 2.6;
  return m;
}

// Staggered grid: vertices at s = (i - 1/2) h, i = 0..n+1, h = L / n. The clamped edge
// (vertices 0 and 1, and its twist) has its midpoint at the clamp s = 0; interior vertices
// 1..n have Voronoi cells [(i-1) h, i h] tiling [0, L]; the last edge's midpoint is the rod's
// end s = L, where end loads act (half on each of its vertices). This is the midpoint rule,
// second order (a ghost vertex at s = -h with the clamp at a vertex is only first order).
Eigen::MatrixX3d clamped_line(int n, double L) {
  Eigen::MatrixX3d x = Eigen::MatrixX3d::Zero(n + 2, 3);
  for (int i = 0; i < n + 2; ++i) x(i, 0) = (i - 0.5) * L / n;
  return x;
}

NewtonResult solve(const Model& model, const Vector& p, Vector& x, int max_iterations = 200) {
  NewtonOptions o;
  o.max_iterations = max_iterations;
  o.relative_tolerance = 1e-12;
  if (std::getenv("ROD_DEBUG")) o.progress = &std::cout;
  NewtonSolver newton(model, o);
  Vector y = model.elimination().restrict_state(x);
  NewtonResult r = newton.solve(p, y);
  x = model.state(y, p);
  return r;
}

TEST(RodValidation, ElasticaReferenceMatchesSmallDeflectionTheory) {
  // alpha -> 0: deflection P L^3 / (3 EI) (Euler-Bernoulli), x_tip -> L.
  const double alpha = 1e-4;
  const Eigen::Vector2d tip = elastica_tip(alpha, 1.0);
  EXPECT_NEAR(tip[1] / (alpha / 3.0), 1.0, 1e-4);
  EXPECT_NEAR(tip[0], 1.0, 1e-8);
}

// A dead load f scaled by a load factor (for load stepping): E = -factor f . x.
class ScaledLoad final : public EnergyTerm {
 public:
  explicit ScaledLoad(Vector f) : f_(std::move(f)) {}
  std::string name() const override { return "scaled_load"; }
  void evaluate(const Vector& x, const Vector&, const EnergyRequest& r) const override {
    if (r.value) *r.value -= factor * f_.dot(x);
    if (r.gradient) *r.gradient -= factor * f_;
  }
  double factor = 1.0;

 private:
  Vector f_;
};

double cantilever_tip_error(int n, double alpha, Eigen::Vector2d* tip_out = nullptr) {
  const double L = 1.0;
  // r = 3e-3: axial strain ~ 1e-5, far below the discretization error at n = 80; stiffer rods
  // need many more Newton iterations (the linearized rotations stretch the edges).
  const int steps = 1;
  RodSetup s = make_rod(clamped_line(n, L), unit_bending_material(3e-3), Eigen::Vector3d::UnitZ());
  Vector forces = Vector::Zero(s.model->num_dofs());
  add_point_load(*s.rod, n, Eigen::Vector3d(0.0, -0.5 * alpha, 0.0), forces);  // EI = 1, L = 1
  add_point_load(*s.rod, n + 1, Eigen::Vector3d(0.0, -0.5 * alpha, 0.0), forces);
  auto& load = s.model->add(std::make_unique<ScaledLoad>(forces));
  s.model->set_elimination(Elimination::dirichlet(clamped_end_dofs(*s.rod, RodEnd::first), s.rest));
  Vector x = s.rest;
  int iterations = 0;
  for (int step = 1; step <= steps; ++step) {
    load.factor = double(step) / steps;
    const NewtonResult r = solve(*s.model, s.p, x);
    iterations += r.iterations;
    EXPECT_TRUE(r.converged()) << r.report();
    s.rod->update_reference_frames(x);
  }
  if (std::getenv("ROD_DEBUG")) std::printf("n = %d: %d Newton iterations\n", n, iterations);
  EXPECT_LT(iterations, 100);
  const Eigen::Vector3d tip = 0.5 * (s.rod->position(x, n) + s.rod->position(x, n + 1));
  const Eigen::Vector2d ref = elastica_tip(alpha, L);
  if (tip_out) *tip_out = tip.head<2>();
  return std::hypot(tip[0] - ref[0], -tip[1] - ref[1]) / L;
}

TEST(RodValidation, CantileverLargeTipLoadMatchesElasticaAtSecondOrder) {
  const double alpha = 5.0;  // tip rotation ~ 60 degrees, deflection ~ 0.71 L
  std::vector<double> errors;
  for (int n : {10, 20, 40, 80}) errors.push_back(cantilever_tip_error(n, alpha));
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double rate = std::log2(errors[i - 1] / errors[i]);
    EXPECT_GT(rate, 1.8) << "n = " << (10 << i) << " error " << errors[i];
  }
  EXPECT_LT(errors.back(), 1e-3);
  std::printf("cantilever alpha = 5: tip errors / L at n = 10, 20, 40, 80: %.3e %.3e %.3e %.3e\n", errors[0],
              errors[1], errors[2], errors[3]);
}

// Circumradius of three points.
double circumradius(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double ab = (b - a).norm(), bc = (c - b).norm(), ca = (a - c).norm();
  return ab * bc * ca / (2.0 * (b - a).cross(c - a).norm());
}

double end_moment_radius_error(int n, double moment) {
  RodSetup s = make_rod(clamped_line(n, 1.0), unit_bending_material(3e-3), Eigen::Vector3d::UnitZ());
  s.model->add(
      std::make_unique<RodEndMomentTerm>(*s.rod, s.rod->num_edges() - 1, Eigen::Vector3d::UnitZ(), moment));
  // The planar elastica: the moment acts about z on the edge's angle in the xy-plane, which is
  // only a conservative end couple for in-plane motion, so z and the twists are held.
  std::vector<int> fixed = clamped_end_dofs(*s.rod, RodEnd::first);
  for (int v = 0; v < s.rod->num_vertices(); ++v) fixed.push_back(s.rod->position_dof(v, 2));
  for (int j = 1; j < s.rod->num_edges(); ++j) fixed.push_back(s.rod->twist_dof(j));
  std::sort(fixed.begin(), fixed.end());
  fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
  s.model->set_elimination(Elimination::dirichlet(fixed, s.rest));
  Vector x = s.rest;
  const NewtonResult r = solve(*s.model, s.p, x);
  EXPECT_TRUE(r.converged()) << r.report();
  const double R =
      circumradius(s.rod->position(x, 1), s.rod->position(x, n / 2 + 1), s.rod->position(x, n + 1));
  return std::abs(R - 1.0 / moment) * moment;
}

TEST(RodValidation, EndMomentBendsRodIntoCircularArcOfRadiusEIOverM) {
  const double M = 2.0;  // arc of 2 rad, radius 0.5
  std::vector<double> errors;
  for (int n : {10, 20, 40}) errors.push_back(end_moment_radius_error(n, M));
  for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_GT(std::log2(errors[i - 1] / errors[i]), 1.9);
  EXPECT_LT(errors.back(), 1e-3);
  std::printf("end moment: relative radius errors at n = 10, 20, 40: %.3e %.3e %.3e\n", errors[0], errors[1],
              errors[2]);
}

// Smallest eigenvalue of the reduced exact Hessian of a pinned-pinned column (vertex 0 held,
// vertex n held in y and z, first twist held) in its straight state under axial load P.
double smallest_column_eigenvalue(RodSetup& s, double P) {
  const int n = s.rod->num_edges();
  const double EA = s.material.youngs_modulus * M_PI * s.material.radius * s.material.radius;
  Vector x = s.rest;
  for (int v = 0; v <= n; ++v) x[s.rod->position_dof(v, 0)] *= 1.0 - P / EA;  // uniform compression
  SparseMatrix H(x.size(), x.size());
  for (const auto& term : s.model->terms()) H += term->hessian(x, s.p, HessianMode::exact);
  const SparseMatrix& S = s.model->elimination().basis();
  const Matrix reduced = Matrix(S.transpose() * H * S);
  return symmetric_eigenvalues(reduced)[0];
}

double buckling_load(int n) {
  RodSetup s = make_rod(straight(n + 1, 1.0), unit_bending_material(1e-3), Eigen::Vector3d::UnitZ());
  std::vector<int> fixed = pinned_vertex_dofs(*s.rod, 0);
  fixed.push_back(s.rod->position_dof(n, 1));
  fixed.push_back(s.rod->position_dof(n, 2));
  fixed.push_back(s.rod->twist_dof(0));
  s.model->set_elimination(Elimination::dirichlet(fixed, s.rest));
  double lo = 5.0, hi = 15.0;  // pi^2 ~ 9.87 (EI = L = 1)
  EXPECT_GT(smallest_column_eigenvalue(s, lo), 0.0);
  EXPECT_LT(smallest_column_eigenvalue(s, hi), 0.0);
  for (int it = 0; it < 50; ++it) {
    const double mid = 0.5 * (lo + hi);
    (smallest_column_eigenvalue(s, mid) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(RodValidation, EulerBucklingLoadOfPinnedColumn) {
  const double euler = M_PI * M_PI;  // EI = 1, L = 1
  std::vector<double> errors;
  for (int n : {10, 20, 40}) errors.push_back(std::abs(buckling_load(n) - euler) / euler);
  for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_GT(std::log2(errors[i - 1] / errors[i]), 1.9);
  EXPECT_LT(errors.back(), 1e-3);
  std::printf("Euler buckling: relative load errors at n = 10, 20, 40: %.3e %.3e %.3e\n", errors[0],
              errors[1], errors[2]);
}

TEST(RodValidation, FiftyTurnsOfTwistOnAClampedRod) {
  const int n = 20;
  RodSetup s = make_rod(straight(n + 1, 1.0), unit_bending_material(1e-2));
  const double turns = 50.0, Phi = 2.0 * M_PI * turns;
  Vector x0 = s.rest;
  x0[s.rod->twist_dof(n - 1)] = Phi;
  std::vector<int> fixed = clamped_end_dofs(*s.rod, RodEnd::first);
  for (int d : clamped_end_dofs(*s.rod, RodEnd::last)) fixed.push_back(d);
  s.model->set_elimination(Elimination::dirichlet(fixed, x0));
  Vector x = x0;
  const NewtonResult r = solve(*s.model, s.p, x);
  ASSERT_TRUE(r.converged()) << r.report();
  // Uniform twist between the first and last edge midpoints, a distance L' = (n - 1) h apart.
  const double h = 1.0 / n, Lp = (n - 1) * h;
  const double GJ = s.material.shear_modulus * M_PI * std::pow(s.material.radius, 4) / 2.0;
  for (int j = 0; j < n; ++j) EXPECT_NEAR(x[s.rod->twist_dof(j)], Phi * j / (n - 1), 1e-9 * Phi);
  EXPECT_NEAR(s.model->energy(x, s.p), GJ * Phi * Phi / (2.0 * Lp), 1e-9 * GJ * Phi * Phi / Lp);
}

}  // namespace
}  // namespace tailor::rod_validation_test
