// The meshless elastic term (forward/meshless/meshless_elastic_term.hpp): derivative checks
// (gradient, Hessian, dE/dp, mixed block and its transpose product) for every registered
// material with per-node E and nu, the projected Hessian's semidefiniteness, zero energy and
// force at rest, and affine deformations integrated exactly.
#include "forward/meshless/meshless_elastic_term.hpp"

#include <gtest/gtest.h>

#include <omp.h>

#include "forward/core/symmetric_eigen.hpp"
#include <random>
#include <map>
#include <set>

#include "adjoint/derivative_check.hpp"
#include "forward/fem/material_registry.hpp"
#include "meshless_fixtures.hpp"

namespace tailor::meshless_elastic_term_test {
namespace {

using namespace tailor::meshless_testing;

MeshlessSolid small_solid() {
  return make_solid(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.5, 1, 1)), 0.5, 2, 0);
}

std::unique_ptr<MeshlessElasticTerm<3>> term_of(const MeshlessSolid& s, const std::string& material) {
  return std::make_unique<MeshlessElasticTerm<3>>(s.quadrature, make_material<3>(parse_material_kind(material)), 0,
                                                  s.num_nodes());
}

// Per-node E in [80, 120] and nu in [0.25, 0.35].
Vector varied_parameters(int nodes, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector p(2 * nodes);
  for (int a = 0; a < nodes; ++a) {
    p[a] = 100.0 + 20.0 * u(rng);
    p[nodes + a] = 0.3 + 0.05 * u(rng);
  }
  return p;
}

class MeshlessElasticTermTest : public ::testing::TestWithParam<std::string> {};

TEST_P(MeshlessElasticTermTest, DerivativesMatchDifferences) {
  const MeshlessSolid s = small_solid();
  const auto term = term_of(s, GetParam());
  const Vector p = varied_parameters(s.num_nodes(), 5);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // A stretched, sheared state with a random perturbation of every coefficient.
  Eigen::Matrix3d A;
  A << 1.1, 0.2, 0.0, -0.1, 0.95, 0.1, 0.05, 0.0, 1.05;
  Vector x = s.rest();
  for (int a = 0; a < s.num_nodes(); ++a) x.segment<3>(3 * a) = A * x.segment<3>(3 * a);
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += 0.03 * u(rng);
  for (HessianMode mode : {HessianMode::exact}) {
    DerivativeCheckOptions options;
    options.hessian_mode = mode;
    options.initial_step = 1e-4;
    options.tolerance = 2e-6;
    const EnergyTermCheck c = check_energy_term(*term, x, p, options);
    EXPECT_TRUE(c.passed()) << GetParam() << "\n" << c.table();
    std::set<std::string> checked;
    for (const auto& one : c.checks) {
      checked.insert(one.quantity);
      EXPECT_FALSE(one.vanishing) << one.quantity;
    }
    for (const char* quantity : {"gradient", "hessian", "param_gradient", "mixed", "mixed_transpose"})
      EXPECT_TRUE(checked.count(quantity)) << quantity << " was not checked";
  }
}

TEST_P(MeshlessElasticTermTest, ProjectedHessianIsPositiveSemidefinite) {
  const MeshlessSolid s = small_solid();
  const auto term = term_of(s, GetParam());
  const Vector p = varied_parameters(s.num_nodes(), 6);
  Vector x = s.rest();
  for (int a = 0; a < s.num_nodes(); ++a) x[3 * a] *= 0.6;  // compressed along x
  const Eigen::MatrixXd H = Eigen::MatrixXd(term->hessian(x, p, HessianMode::projected));
  EXPECT_LT((H - H.transpose()).norm(), 1e-10 * H.norm());
  const Eigen::VectorXd lambda = symmetric_eigenvalues(H);
  EXPECT_GT(lambda.minCoeff(), -1e-9 * lambda.maxCoeff()) << GetParam();
}

TEST_P(MeshlessElasticTermTest, RestIsStressFreeAndAffineStatesAreIntegratedExactly) {
  const MeshlessSolid s = small_solid();
  const auto term = term_of(s, GetParam());
  const Vector p = uniform_parameters(s.num_nodes(), 100.0, 0.3);
  const Vector rest = s.rest();
  Vector g = Vector::Zero(rest.size());
  EXPECT_NEAR(term->value(rest, p), 0.0, 1e-12);
  term->add_gradient(rest, p, g);
  EXPECT_LT(g.norm(), 1e-10);
  // x_a = A X_a + c: F_q = A at every point, so E = volume * Psi(A).
  Eigen::Matrix3d A;
  A << 1.2, 0.1, -0.05, 0.0, 0.9, 0.2, 0.1, 0.0, 1.1;
  Vector x = rest;
  for (int a = 0; a < s.num_nodes(); ++a) x.segment<3>(3 * a) = A * rest.segment<3>(3 * a) + Eigen::Vector3d(1, 2, 3);
  for (int q = 0; q < s.quadrature->num_points(); ++q)
    EXPECT_LT((s.quadrature->deformation_gradient(x, q) - A).norm(), 1e-12);
  MaterialEvaluation<3> m;
  term->material().evaluate(A, lame_from_young_poisson(100.0, 0.3), false, false, HessianMode::exact, m);
  EXPECT_NEAR(term->value(x, p), s.sampling.volume() * m.energy_density, 1e-11 * std::abs(m.energy_density));
}

INSTANTIATE_TEST_SUITE_P(EveryMaterial, MeshlessElasticTermTest, ::testing::ValuesIn(material_names()),
                         [](const auto& param_info) { return param_info.param; });

TEST(MeshlessElasticTerm, ParallelLoopIsDeterministicAndItsHessianExactlySymmetric) {
  // 225 nodes and 1,024 points: both parallel loops run. 1, 2 and 3 OpenMP threads give the same
  // bits, and each block (b, a) of two nodes is the transpose of (a, b) (summed once, mirrored).
  const MeshlessSolid s = make_solid(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1)), 0.25, 2, 0);
  ASSERT_GT(s.num_nodes(), 64);
  ASSERT_GT(s.quadrature->num_points(), 256);
  const auto term = term_of(s, "neo_hookean");
  Vector x = s.rest();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.03, 0.03);
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += u(rng);
  const Vector p = varied_parameters(s.num_nodes(), 4);
  HessianPattern pattern;
  term->hessian_pattern(pattern);
  struct Evaluation {
    double value = 0.0;
    Vector gradient;
    std::vector<double> hessian;
  };
  const auto evaluate = [&]() {
    Evaluation e;
    e.gradient = Vector::Zero(x.size());
    e.hessian.assign(pattern.size(), -1.0);  // every slot must be written
    EnergyRequest request;
    request.value = &e.value;
    request.gradient = &e.gradient;
    request.hessian_values = e.hessian.data();
    term->evaluate(x, p, request);
    return e;
  };
  const int saved_threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const Evaluation serial = evaluate();
  for (int threads : {2, 3}) {
    omp_set_num_threads(threads);
    const Evaluation e = evaluate();
    EXPECT_EQ(e.value, serial.value) << threads << " threads";
    EXPECT_EQ((e.gradient - serial.gradient).lpNorm<Eigen::Infinity>(), 0.0) << threads << " threads";
    EXPECT_TRUE(e.hessian == serial.hessian) << threads << " threads";
  }
  omp_set_num_threads(saved_threads);
  // Slot values by (row, col); the pattern holds both orders of every pair, once each.
  std::map<std::pair<int, int>, double> by_entry;
  for (std::size_t k = 0; k < pattern.size(); ++k) by_entry[{pattern[k].row, pattern[k].col}] = serial.hessian[k];
  ASSERT_EQ(by_entry.size(), pattern.size());
  // Blocks of two nodes mirrored exactly; a node's own block summed, symmetric to round-off.
  double scale = 0.0;
  for (double v : serial.hessian) scale = std::max(scale, std::abs(v));
  for (const auto& [entry, value] : by_entry) {
    const double mirror = by_entry.at({entry.second, entry.first});
    if (entry.first / 3 != entry.second / 3)
      EXPECT_EQ(value, mirror);
    else
      EXPECT_NEAR(value, mirror, 1e-14 * scale);
  }
}

TEST(MeshlessElasticTerm, ConstantHessianOnlyForTheLinearMaterial) {
  const MeshlessSolid s = small_solid();
  EXPECT_TRUE(term_of(s, "linear")->hessian_is_constant());
  EXPECT_FALSE(term_of(s, "neo_hookean")->hessian_is_constant());
  EXPECT_THROW(MeshlessElasticTerm<3>(nullptr, make_material<3>(MaterialKind::linear), 0, 0), std::invalid_argument);
  EXPECT_THROW(MeshlessElasticTerm<3>(s.quadrature, nullptr, 0, 0), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::meshless_elastic_term_test
