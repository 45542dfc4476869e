#include "forward/core/assembler.hpp"

#include <gtest/gtest.h>

#include "../../support/quadratic_term.hpp"

namespace tailor {
namespace {

using testing::QuadraticTerm;
using testing::random_spd;

// Reduced gradient and Hessian of the assembler must equal S^T g and S^T H S for Dirichlet
// (selection) and for a general basis with merged and weighted DOFs.
void expect_reduction_matches(const Elimination& elimination) {
  const int n = elimination.num_dofs();
  const SparseMatrix A = random_spd(n, 7);
  const Vector b = Vector::LinSpaced(n, -1.0, 2.0);
  Model model(n);
  model.add(std::make_unique<QuadraticTerm>(A, b));
  model.set_elimination(elimination);
  ReducedAssembler assembler(model);
  const Vector y = Vector::LinSpaced(elimination.num_free(), 0.3, -0.7);
  Vector p(1);
  p[0] = 0.25;
  double energy = 0;
  Vector gy;
  SparseMatrix hy = assembler.hessian_pattern_matrix();
  assembler.evaluate(y, p, &energy, &gy, &hy);

  const Vector x = elimination.expand(y);
  const SparseMatrix& S = elimination.basis();
  const SparseMatrix H = model.terms()[0]->hessian(x, p, HessianMode::exact);
  const Matrix expected_h = Matrix(S.transpose() * H * S);
  const Matrix got_h = Matrix(SparseMatrix(hy.selfadjointView<Eigen::Upper>()));
  EXPECT_NEAR(energy, model.energy(x, p), 1e-12 * std::abs(energy));
  EXPECT_LT((gy - S.transpose() * model.gradient(x, p)).norm(), 1e-12 * gy.norm());
  EXPECT_LT((got_h - expected_h).norm(), 1e-12 * expected_h.norm());
  // Re-assembly overwrites rather than accumulates.
  assembler.evaluate(y, p, nullptr, nullptr, &hy);
  EXPECT_LT((Matrix(SparseMatrix(hy.selfadjointView<Eigen::Upper>())) - expected_h).norm(), 1e-12 * expected_h.norm());
}

TEST(ReducedAssembler, DirichletMatchesExplicitProjection) {
  const Vector values = Vector::Constant(12, 0.5);
  expect_reduction_matches(Elimination::dirichlet({0, 5, 11}, values));
}

TEST(ReducedAssembler, GeneralBasisMatchesExplicitProjection) {
  // DOFs 0 and 6 share one unknown (periodicity), DOF 3 is a weighted mix of two unknowns,
  // DOF 9 is fixed.
  const int n = 10;
  Triplets t;
  int column = 0;
  std::vector<int> col_of(n, -1);
  for (int i = 0; i < n; ++i) {
    if (i == 6 || i == 9 || i == 3) continue;
    col_of[i] = column++;
    t.emplace_back(i, col_of[i], 1.0);
  }
  t.emplace_back(6, col_of[0], 1.0);
  t.emplace_back(3, col_of[1], 0.5);
  t.emplace_back(3, col_of[2], -2.0);
  SparseMatrix S(n, column);
  S.setFromTriplets(t.begin(), t.end());
  Vector x0 = Vector::Zero(n);
  x0[9] = 1.5;
  const Elimination e(x0, S);
  EXPECT_FALSE(e.is_selection());
  expect_reduction_matches(e);
}

TEST(ParameterLayout, BlocksAreContiguousAndNamed) {
  ParameterLayout layout;
  EXPECT_EQ(layout.add("youngs_modulus", 4), 0);
  EXPECT_EQ(layout.add("poisson_ratio", 4), 4);
  EXPECT_EQ(layout.size(), 8);
  EXPECT_EQ(layout.at("poisson_ratio").offset, 4);
  EXPECT_THROW(layout.add("youngs_modulus", 1), std::invalid_argument);
  EXPECT_THROW(layout.at("density"), std::out_of_range);
}

}  // namespace
}  // namespace tailor
