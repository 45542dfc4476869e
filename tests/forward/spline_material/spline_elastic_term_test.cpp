// SplineElasticTerm: derivative checks in x and in the curve control values (gradient, Hessian,
// parameter gradient, mixed block and its transpose product), a corrupted derivative that the
// check must reject, agreement with ElasticTerm for the exact corotated preset, and Newton on a
// twisted bar and a compressed block.
#include "forward/fem/spline_elastic_term.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <numbers>

#include "adjoint/derivative_check.hpp"
#include "forward/core/model.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/solve/newton.hpp"
#include "tests/forward/spline_material/spline_test_curves.hpp"
#include "tests/support/fem_fixtures.hpp"

namespace tailor::spline_elastic_term_test {
namespace {

using testing::affine_state;
using testing::rest_state;
using testing::small_mesh;

// A deformed state with stretches, shear and one nearly inverted region.
Vector deformed_state(const Mesh& mesh, unsigned seed) {
  const int dim = mesh.dim();
  Matrix A = Matrix::Identity(dim, dim);
  A(0, 0) = 1.3;
  A(0, 1) = 0.2;
  A(dim - 1, 0) = -0.15;
  Vector x = affine_state(mesh, A, Vector::Constant(dim, 0.1));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.08, 0.08);
  for (int i = 0; i < x.size(); ++i) x[i] += u(rng);
  return x;
}

template <int Dim>
void check_term(const PrincipalStretchCurves& curves) {
  const Mesh mesh = small_mesh(Dim);
  const int offset = 3;  // a block that does not start at 0
  const SplineElasticTerm<Dim> term(mesh, curves, offset);
  Vector p = Vector::Zero(offset + curves.num_controls() + 2);
  p.segment(offset, curves.num_controls()) = curves.controls();
  const Vector x = deformed_state(mesh, 4);
  DerivativeCheckOptions options;
  options.parameter_floor = 0.1;
  const EnergyTermCheck c = check_energy_term(term, x, p, options);
  EXPECT_TRUE(c.passed()) << c.table();
  int checked = 0;
  for (const auto& d : c.checks) checked += d.passed && !d.vanishing;
  EXPECT_GE(checked, 5) << c.table();
}

TEST(SplineElasticTerm, DerivativeChecksPass3d) { check_term<3>(test::generic_curves()); }
TEST(SplineElasticTerm, DerivativeChecksPass2d) { check_term<2>(test::generic_curves()); }

// Forwards to a term but scales the mixed block (and the parameter gradient) by 1 + 1e-3.
class SkewedTerm final : public EnergyTerm {
 public:
  explicit SkewedTerm(const EnergyTerm& inner) : inner_(inner) {}
  std::string name() const override { return "skewed"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& r) const override {
    inner_.evaluate(x, p, r);
  }
  void hessian_pattern(HessianPattern& pattern) const override { inner_.hessian_pattern(pattern); }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gp) const override {
    Vector g = Vector::Zero(gp.size());
    inner_.add_param_gradient(x, p, g);
    gp += (1 + 1e-3) * g;
  }
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override {
    Triplets t;
    inner_.add_mixed(x, p, t);
    for (const auto& e : t) mixed.emplace_back(e.row(), e.col(), (1 + 1e-3) * e.value());
  }

 private:
  const EnergyTerm& inner_;
};

TEST(SplineElasticTerm, CorruptedParameterDerivativesFailTheCheck) {
  const Mesh mesh = small_mesh(3);
  const auto curves = test::generic_curves();
  const SplineElasticTerm<3> term(mesh, curves, 0);
  const SkewedTerm skewed(term);
  const EnergyTermCheck c = check_energy_term(skewed, deformed_state(mesh, 4), curves.controls());
  EXPECT_FALSE(c.passed()) << c.table();
  for (const auto& d : c.checks)
    if (d.quantity == "param_gradient" || d.quantity == "mixed") {
      EXPECT_FALSE(d.passed) << d.quantity;
      EXPECT_FALSE(d.vanishing) << d.quantity;
    }
}

// Bar [0, 4] x [0, 1]^2: the end x = 0 clamped, the end x = 4 turned by `angle` about the bar
// axis and pushed by `shortening` along it; solves with the given term.
struct BarSolve {
  NewtonResult result;
  Vector x;
};
BarSolve solve_bar(const Mesh& mesh, std::unique_ptr<EnergyTerm> term, const Vector& p, double angle,
                   double shortening, double length) {
  Model model(3 * mesh.num_vertices());
  model.parameter_layout().add("p", static_cast<int>(p.size()));
  model.add(std::move(term));
  Vector target = rest_state(mesh);
  std::vector<int> fixed;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()).toRotationMatrix();
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d X = mesh.rest_positions.row(v).transpose();
    if (X.x() < 1e-12 || X.x() > length - 1e-12) {
      for (int k = 0; k < 3; ++k) fixed.push_back(3 * v + k);
      if (X.x() > length - 1e-12) {
        const Eigen::Vector3d c(length, 0.5, 0.5);
        target.segment<3>(3 * v) = c + R * (X - c) - Eigen::Vector3d(shortening, 0, 0);
      }
    }
  }
  model.set_elimination(Elimination::dirichlet(fixed, target));
  NewtonSolver solver(model);
  Vector y = model.elimination().restrict_state(rest_state(mesh));
  BarSolve s;
  s.result = solver.solve(p, y);
  s.x = model.elimination().expand(y);
  return s;
}

TEST(SplineElasticTerm, NewtonConvergesOnATwistedBarWhereNeoHookeanDoes) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 1, 1), 8, 2, 2);
  const int m = mesh.num_elements();
  const double E = 1e3, nu = 0.35;
  Vector pe(2 * m);
  pe.head(m).setConstant(E);
  pe.tail(m).setConstant(nu);
  const auto nh = solve_bar(
      mesh, std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::neo_hookean), 0, m), pe,
      std::numbers::pi / 2, 0.0, 4.0);
  ASSERT_TRUE(nh.result.converged()) << nh.result.report();
  const auto curves = principal_stretch_preset(SplinePreset::neo_hookean, lame_from_young_poisson(E, nu));
  const auto spline = solve_bar(mesh, std::make_unique<SplineElasticTerm<3>>(mesh, curves, 0),
                                curves.controls(), std::numbers::pi / 2, 0.0, 4.0);
  ASSERT_TRUE(spline.result.converged()) << spline.result.report();
  EXPECT_LE(spline.result.iterations, 2 * nh.result.iterations + 5);
  // Same small-strain response, different large-strain regulariser: close, not equal.
  EXPECT_LT((spline.x - nh.x).lpNorm<Eigen::Infinity>(), 0.1);
}

// The exact corotated preset reproduces ElasticTerm with the corotated material: same
// equilibrium of a block compressed by 30% and twisted by 30 degrees.
TEST(SplineElasticTerm, CompressedBlockMatchesTheCorotatedMaterial) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), 3, 3, 3);
  const int m = mesh.num_elements();
  const double E = 1e3, nu = 0.3;
  Vector pe(2 * m);
  pe.head(m).setConstant(E);
  pe.tail(m).setConstant(nu);
  const auto reference =
      solve_bar(mesh, std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::corotated), 0, m),
                pe, std::numbers::pi / 6, 0.3, 1.0);
  ASSERT_TRUE(reference.result.converged()) << reference.result.report();
  const auto curves = principal_stretch_preset(SplinePreset::corotated, lame_from_young_poisson(E, nu));
  const auto spline = solve_bar(mesh, std::make_unique<SplineElasticTerm<3>>(mesh, curves, 0),
                                curves.controls(), std::numbers::pi / 6, 0.3, 1.0);
  ASSERT_TRUE(spline.result.converged()) << spline.result.report();
  EXPECT_LT((spline.x - reference.x).lpNorm<Eigen::Infinity>(), 1e-8);
  // The stable Neo-Hookean converges on the same block, and so does the Neo-Hookean preset.
  const auto stable = solve_bar(
      mesh, std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::neo_hookean), 0, m), pe,
      std::numbers::pi / 6, 0.3, 1.0);
  ASSERT_TRUE(stable.result.converged()) << stable.result.report();
  const auto nh_curves = principal_stretch_preset(SplinePreset::neo_hookean, lame_from_young_poisson(E, nu));
  const auto nh = solve_bar(mesh, std::make_unique<SplineElasticTerm<3>>(mesh, nh_curves, 0),
                            nh_curves.controls(), std::numbers::pi / 6, 0.3, 1.0);
  EXPECT_TRUE(nh.result.converged()) << nh.result.report();
}

// Regions: two terms over complementary element sets, each with its own control block, equal
// one term over all elements when the blocks hold the same controls, and their parameter
// gradients land in their own blocks.
TEST(SplineElasticTerm, RegionsWithTheirOwnControlBlocks) {
  const Mesh mesh = small_mesh(3);
  const auto curves = test::generic_curves();
  const int n = curves.num_controls();
  std::vector<int> first, second;
  for (int e = 0; e < mesh.num_elements(); ++e) (e % 3 == 0 ? first : second).push_back(e);
  const SplineElasticTerm<3> all(mesh, curves, 0), a(mesh, curves, 0, first), b(mesh, curves, n, second);
  Vector p(2 * n);
  p << curves.controls(), curves.controls();
  const Vector x = deformed_state(mesh, 7);
  EXPECT_NEAR(a.value(x, p) + b.value(x, p), all.value(x, p.head(n)),
              1e-12 * std::abs(all.value(x, p.head(n))));
  Vector ga = Vector::Zero(2 * n), gall = Vector::Zero(n);
  a.add_param_gradient(x, p, ga);
  b.add_param_gradient(x, p, ga);
  all.add_param_gradient(x, p.head(n), gall);
  EXPECT_LT((ga.head(n) + ga.tail(n) - gall).norm(), 1e-12 * gall.norm());
  EXPECT_GT(ga.head(n).norm(), 0.0);
  EXPECT_GT(ga.tail(n).norm(), 0.0);
  DerivativeCheckOptions options;
  options.parameter_floor = 0.1;
  const EnergyTermCheck c = check_energy_term(b, x, p, options);
  EXPECT_TRUE(c.passed()) << c.table();
}

TEST(SplineElasticTerm, RejectsAShortParameterVector) {
  const Mesh mesh = small_mesh(2);
  const auto curves = test::generic_curves();
  const SplineElasticTerm<2> term(mesh, curves, 2);
  EXPECT_THROW(term.value(rest_state(mesh), Vector::Zero(curves.num_controls())), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::spline_elastic_term_test
